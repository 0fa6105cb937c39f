"""Reads an issv MCAP recording: seeks when the file is whole, survives a file cut short.

A complete file (footer and summary present) is read from the chunk that holds the seek time,
found through the summary's chunk index. A file cut short by a crash has no summary: it is read
from the start, record by record, up to the last whole record, and `truncated_at` says where it
stopped. Anything else that does not parse is corruption: one UserError with the byte offset.
"""
from __future__ import annotations

import io
import struct
import sys
from contextlib import contextmanager
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Iterator

import numpy as np
from mcap.data_stream import ReadDataStream
from mcap.exceptions import McapError
from mcap.opcode import Opcode
from mcap.reader import SeekingReader
from mcap.records import Channel, Chunk, Header, Message, Metadata
from mcap.stream_reader import CRCValidationError, breakup_chunk

from host.errors import UserError
from host.model import DepthFrame, Frame, Gesture
from host.recording import codec

MAGIC = b"\x89MCAP0\r\n"
_KNOWN = {int(op) for op in Opcode}
_PARSE_ERRORS = (codec.FormatError, McapError, CRCValidationError, struct.error, UnicodeDecodeError,
                 ValueError, KeyError, TypeError)


@dataclass(frozen=True)
class _Record:
    offset: int  # byte offset of the record in the file
    opcode: int
    body: bytes

    def stream(self) -> ReadDataStream:
        return ReadDataStream(io.BytesIO(self.body))


class Recording:
    """An issv recording on disk. `frames()` and `depth_frames()` iterate it (each call restarts)."""

    def __init__(self, path: str | Path, warn=None) -> None:
        self.path = Path(path)
        self._warn = warn or (lambda text: print(f"issv: {text}", file=sys.stderr))
        self.end_gestures: tuple[Gesture, ...] = ()  # known once frames() has been read to the end
        try:
            self._file = open(self.path, "rb")
        except FileNotFoundError:
            raise UserError(f"{self.path}: no such recording") from None
        except OSError as error:
            raise UserError(f"{self.path}: cannot read the recording: {error.strerror or error}") from None
        self.size = self.path.stat().st_size
        if self._file.read(8) != MAGIC:
            self._file.close()
            raise UserError(f"{self.path}: not an MCAP recording (no MCAP magic at byte 0); "
                            f"record one with `issv record PROFILE -o FILE.mcap`")
        self.truncated_at: int | None = None
        self._summary = self._read_summary()
        self.meta: dict[str, str] = {}
        self.library = ""
        self._read_preamble()
        if self.meta.get("format", codec.FORMAT).split("/")[0] != codec.FORMAT.split("/")[0]:
            raise UserError(f"{self.path}: an MCAP file but not an issv recording (format {self.meta.get('format')!r})")

    @property
    def complete(self) -> bool:
        """True when the file was closed properly (it has its summary and footer)."""
        return self._summary is not None

    def close(self) -> None:
        self._file.close()

    def __enter__(self) -> "Recording":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- records -------------------------------------------------------------------------------
    def _read_summary(self):
        try:
            self._file.seek(0)
            summary = SeekingReader(self._file).get_summary()
        except Exception:  # no footer or a broken one: the file was cut short; stream it instead
            return None
        return summary if summary is not None and summary.chunk_indexes else None

    @contextmanager
    def _at(self, offset: int, what: str):
        try:
            yield
        except UserError:
            raise
        except _PARSE_ERRORS as error:
            raise UserError(f"{self.path}: corrupt recording at byte {offset} ({what}): "
                            f"{type(error).__name__}: {error}") from None

    def _records(self, offset: int) -> Iterator[_Record]:
        """Top-level records from `offset` to the end of the data section, or to where the file stops.
        Seeks before every read, so that several iterations over one file may interleave."""
        f = self._file
        while True:
            f.seek(offset)
            head = f.read(9)
            if len(head) < 9:
                return self._cut(offset)
            opcode, length = struct.unpack("<BQ", head)
            if opcode not in _KNOWN:
                raise UserError(f"{self.path}: corrupt recording at byte {offset}: unknown MCAP record type "
                                f"0x{opcode:02x} (the file is damaged from there on)")
            if offset + 9 + length > self.size:
                return self._cut(offset)
            record = _Record(offset, opcode, f.read(length))
            if opcode in (Opcode.DATA_END, Opcode.FOOTER):
                return None
            yield record
            offset += 9 + length

    def _cut(self, offset: int) -> None:
        if self.truncated_at is None:
            self._warn(f"{self.path}: the recording stops at byte {offset} of {self.size} without its footer "
                       f"(cut short, e.g. by a crash); reading it up to there")
        self.truncated_at = offset

    def _read_preamble(self) -> None:
        """Header and metadata: written before the first chunk."""
        for record in self._records(8):
            with self._at(record.offset, "the header record there"):
                if record.opcode == Opcode.HEADER:
                    self.library = Header.read(record.stream()).library
                elif record.opcode == Opcode.METADATA:
                    meta = Metadata.read(record.stream())
                    if meta.name == "issv":
                        self.meta = dict(meta.metadata)
                elif record.opcode in (Opcode.CHUNK, Opcode.MESSAGE):
                    return

    def _messages(self, start: float) -> Iterator[tuple[str, Message, int]]:
        """(topic, message, offset of its record) in file order, from source time `start` on."""
        channels: dict[int, str] = {}
        offset = 8
        origin = self._origin() if start > 0 else None
        target = None if origin is None else origin + codec.seconds_to_ns(start)
        if target is not None and self._summary is not None:
            channels = {cid: c.topic for cid, c in self._summary.channels.items()}
            later = [c for c in self._summary.chunk_indexes if c.message_end_time >= target]
            offset = min((c.chunk_start_offset for c in later), default=self.size)
        for record in self._records(offset):
            if record.opcode == Opcode.CHANNEL:
                with self._at(record.offset, "the channel record there"):
                    channel = Channel.read(record.stream())
                channels[channel.id] = channel.topic
            elif record.opcode == Opcode.MESSAGE:
                with self._at(record.offset, "the message record there"):
                    inner = [Message.read(record.stream(), len(record.body))]
                yield from self._keep(inner, channels, target, record.offset)
            elif record.opcode == Opcode.CHUNK:
                with self._at(record.offset, "the chunk record there"):
                    inner = breakup_chunk(Chunk.read(record.stream()), validate_crc=True)
                for r in inner:
                    if isinstance(r, Channel):
                        channels[r.id] = r.topic
                yield from self._keep([r for r in inner if isinstance(r, Message)], channels, target, record.offset)

    def _keep(self, messages, channels, target, offset):
        for m in messages:
            if target is not None and m.log_time < target:
                continue
            topic = channels.get(m.channel_id)
            if topic is None:
                raise UserError(f"{self.path}: corrupt recording at byte {offset}: a message on channel "
                                f"{m.channel_id}, which was never declared")
            yield topic, m, offset

    def _origin(self) -> int | None:
        """Log time (ns) of the first message: where `start` seconds count from."""
        if self._summary is not None and self._summary.statistics is not None:
            return self._summary.statistics.message_start_time
        for _, message, _ in self._messages(0.0):
            return message.log_time
        return None

    # -- frames --------------------------------------------------------------------------------
    def frames(self, start: float = 0.0) -> Iterator[Frame]:
        """Frames exactly as they were tracked: same seq, hands, gestures, source timestamps. Once
        they are all read, `end_gestures` holds the gestures after the last frame (the ones the
        end of the source completed)."""
        depth: codec.DepthHeader | None = None
        decoded: DepthFrame | None = None
        labels: tuple[int, np.ndarray] | None = None  # (frame_id, labels) of the last depth image
        gestures = []
        for topic, message, offset in self._messages(start):
            with self._at(offset, f"a {topic} message in the record there"):
                if topic == codec.DEPTH:
                    depth, decoded, labels = codec.decode_depth(message.data), None, None
                elif topic == codec.LABELS:
                    labels = codec.decode_labels(message.data)
                elif topic == codec.GESTURES:
                    doc = codec.decode_json(message.data)
                    gestures.append(codec.checked(codec.gesture_from_json, doc, "gesture"))
                elif topic == codec.HANDS:
                    doc = codec.decode_json(message.data)
                    frame_depth = frame_labels = None
                    if depth is not None and doc.get("depth_id") == depth.frame_id:
                        decoded = frame_depth = decoded or depth.decode()
                        if labels is not None and labels[0] == depth.frame_id:
                            frame_labels = labels[1]
                    hands = tuple(codec.checked(codec.hand_from_json, h, "hands") for h in doc["hands"])
                    users = codec.checked(codec.users_from_json, doc, "hands")
                    yield Frame(int(doc["seq"]), float(doc["capture_time"]), frame_depth, hands,
                                tuple(gestures), str(doc.get("backend", "")), users=users,
                                time=float(doc["t"]), make_user_labels=_constant(frame_labels))
                    gestures = []
        self.end_gestures = tuple(gestures)

    def depth_headers(self, start: float = 0.0) -> Iterator[tuple[codec.DepthHeader, int]]:
        """Each depth message's header, pixels still compressed, and the offset of its record."""
        for topic, message, offset in self._messages(start):
            if topic == codec.DEPTH:
                with self._at(offset, f"a {topic} message in the record there"):
                    yield codec.decode_depth(message.data), offset

    def depth_frames(self, start: float = 0.0) -> Iterator[DepthFrame]:
        """The depth images alone (for re-tracking by another backend), with their ground truth."""
        for header, offset in self.depth_headers(start):
            with self._at(offset, f"a {codec.DEPTH} message in the record there"):
                yield header.decode()

    def metrics(self) -> list[dict]:
        """The metrics documents recorded during the show (the last one is final if it ended cleanly)."""
        out = []
        for topic, message, offset in self._messages(0.0):
            if topic == codec.METRICS:
                with self._at(offset, f"a {topic} message in the record there"):
                    out.append(codec.decode_json(message.data))
        return out

    def passes(self, depth_only: bool = False, start: float = 0.0, loop: bool = False) -> Iterator[tuple[Any, float]]:
        """(frame or depth frame, time offset) from `start` on; with `loop`, again and again, each
        pass `offset` seconds later than the recording so that time keeps running forwards."""
        offset = 0.0
        while True:
            count, first, last = 0, 0.0, 0.0
            for item in (self.depth_frames(start) if depth_only else self.frames(start)):
                first = item.timestamp if count == 0 else first
                last, count = item.timestamp, count + 1
                yield item, offset
            if not loop or count == 0:
                return
            step = (last - first) / (count - 1) if count > 1 else 1.0 / 30
            offset += last - first + step


def _constant(labels: np.ndarray | None):
    """Frame.make_user_labels for labels read from the file (None: the recording has none)."""
    return None if labels is None else lambda: labels


def shifted_depth(depth: DepthFrame, offset: float, capture_time: float) -> DepthFrame:
    """A depth frame `offset` seconds later (ground-truth gesture intervals too), captured now."""
    truth = depth.truth
    if truth is not None and offset:
        def later(gestures):
            return tuple(replace(g, start=g.start + offset, end=g.end + offset) for g in gestures)
        truth = replace(truth, gestures=later(truth.gestures),
                        users=tuple(replace(u, gestures=later(u.gestures)) for u in truth.users))
    return replace(depth, timestamp=depth.timestamp + offset, capture_time=capture_time, truth=truth)


def shifted_frame(frame: Frame, offset: float, capture_time: float) -> Frame:
    """A recorded frame replayed `offset` seconds later, captured now."""
    depth = None if frame.depth is None else shifted_depth(frame.depth, offset, capture_time)
    gestures = tuple(replace(g, timestamp=g.timestamp + offset) for g in frame.gestures) if offset else frame.gestures
    return replace(frame, depth=depth, gestures=gestures, capture_time=capture_time)
