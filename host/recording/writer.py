"""Writes frames into an MCAP recording as they are tracked (see codec.py for the format)."""
from __future__ import annotations

import json
import threading
import time
from pathlib import Path

from mcap.data_stream import RecordBuilder
from mcap.records import ChunkIndex
from mcap.writer import CompressionType, Writer

from host import __version__
from host.errors import UserError
from host.model import DepthFrame, Frame, Gesture
from host.recording import codec

# A chunk ends at the flush once a second (a crash loses at most about a second of show), or
# sooner past CHUNK_BYTES. The writer keeps every chunk's index until the end, so chunks are not
# made smaller than that: an hour of 640x480 depth at 30 Hz is ~3600 chunks, not ~108000.
CHUNK_BYTES = 4 * 1024 * 1024
FLUSH_EVERY_S = 1.0


class PackedChunkIndexes:
    """The MCAP writer's chunk indexes, kept as the summary's bytes (~90 per chunk, not ~1 kB of
    objects), so an hour-long recording's memory does not grow by its index."""

    def __init__(self) -> None:
        self._data = bytearray()
        self._count = 0

    def append(self, index: ChunkIndex) -> None:
        builder = RecordBuilder()
        index.write(builder)
        self._data += builder.end()
        self._count += 1

    def __len__(self) -> int:
        return self._count

    def __iter__(self):
        """What Writer.finish() does with each index is `index.write(summary)`: all at once here."""
        if self._count:
            yield self

    def write(self, builder: RecordBuilder) -> None:
        builder.write(self._data)


def pack_chunk_indexes(writer: Writer) -> None:
    """mcap's Writer has no option for this, so its private list is swapped for PackedChunkIndexes.
    An mcap that keeps them elsewhere still records (with the index in memory as objects);
    tests/host/test_recording.py fails then, and checks that standard readers read the result."""
    if isinstance(getattr(writer, "_Writer__chunk_indices", None), list):
        writer._Writer__chunk_indices = PackedChunkIndexes()


class RecordingWriter:
    """One recording file. Thread-safe: the sensor thread writes frames, the main thread closes.

    Depth is zstd-compressed per message, so MCAP chunks are left uncompressed (no double work).
    """

    def __init__(self, path: str | Path, meta: dict[str, str] | None = None) -> None:
        self.path = Path(path)
        try:
            self._file = open(self.path, "wb")
        except OSError as error:
            raise UserError(f"{self.path}: cannot write the recording: {error.strerror or error}") from None
        self._lock = threading.Lock()
        self._mcap = Writer(self._file, chunk_size=CHUNK_BYTES, compression=CompressionType.NONE)
        pack_chunk_indexes(self._mcap)
        self._mcap.start(profile="issv", library=f"issv {__version__}")
        self._mcap.add_metadata("issv", {"format": codec.FORMAT, "issv_version": __version__, **(meta or {})})
        self._channels = {codec.DEPTH: self._mcap.register_channel(codec.DEPTH, codec.DEPTH_ENCODING, 0)}
        for topic, schema in codec.SCHEMAS.items():
            sid = self._mcap.register_schema(schema["title"], "jsonschema", json.dumps(schema).encode())
            self._channels[topic] = self._mcap.register_channel(topic, "json", sid)
        self._last_depth: DepthFrame | None = None
        self._last_flush = time.monotonic()
        self._t = 0  # log time (ns) of the last frame, for the metrics messages
        self._seq = 0  # the last frame's seq
        self.frames = 0
        self.closed = False

    def _add(self, topic: str, log_time: int, publish_time: int, data: bytes, seq: int = 0) -> None:
        self._mcap.add_message(self._channels[topic], log_time=log_time, data=data,
                               publish_time=publish_time, sequence=seq)

    def write_frame(self, frame: Frame) -> None:
        """Depth (once per image) and its user labels if the backend knows them, then the frame's
        gestures, then its hands: the frame's last word."""
        log_time = codec.seconds_to_ns(frame.timestamp)
        publish = codec.seconds_to_ns(frame.capture_time)
        with self._lock:
            if self.closed:
                return
            depth = frame.depth
            if depth is not None and depth is not self._last_depth:
                captured = codec.seconds_to_ns(depth.capture_time)
                self._add(codec.DEPTH, log_time, captured, codec.encode_depth(depth), depth.frame_id)
                self._last_depth = depth
                labels = frame.user_labels if frame.make_user_labels is not None else None
                if labels is not None:
                    if codec.LABELS not in self._channels:  # declared with the first labels: none, no channel
                        self._channels[codec.LABELS] = self._mcap.register_channel(codec.LABELS,
                                                                                   codec.LABELS_ENCODING, 0)
                    self._add(codec.LABELS, log_time, captured, codec.encode_labels(depth, labels), depth.frame_id)
            self._add_gestures(frame.gestures, frame.seq, log_time, publish)
            self._add(codec.HANDS, log_time, publish, json.dumps(codec.hands_to_json(frame)).encode(), frame.seq)
            self._t, self._seq = log_time, frame.seq
            self.frames += 1
            if time.monotonic() - self._last_flush >= FLUSH_EVERY_S:
                self._mcap.flush()
                self._last_flush = time.monotonic()

    def write_end_gestures(self, gestures: tuple[Gesture, ...]) -> None:
        """Gestures the end of the source completed: after the last frame, carried by no frame."""
        with self._lock:
            if self.closed:
                return
            self._add_gestures(gestures, self._seq + 1, self._t, codec.seconds_to_ns(time.time()))

    def _add_gestures(self, gestures: tuple[Gesture, ...], seq: int, log_time: int, publish_time: int) -> None:
        for gesture in gestures:
            self._add(codec.GESTURES, log_time, publish_time,
                      json.dumps(codec.gesture_to_json(gesture, seq)).encode(), seq)

    def write_metrics(self, doc: dict, final: bool = False) -> None:
        with self._lock:
            if not self.closed:
                self._add(codec.METRICS, self._t, codec.seconds_to_ns(time.time()),
                          json.dumps({**doc, "final": final}).encode())

    def close(self) -> None:
        """Write the summary and footer (index, statistics) so readers can seek."""
        with self._lock:
            if self.closed:
                return
            self.closed = True
            self._mcap.finish()
            self._file.close()

    def __enter__(self) -> "RecordingWriter":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
