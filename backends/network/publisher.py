"""The sending side of `issv serve`: frames in, ZeroMQ messages out (format: wire.py).

Two sockets, two paths (docs/architecture.md: gestures are events, not samples):
- events (hands and gesture events, heartbeats) on an XPUB socket at ADDR with a high-water mark
  far above any backlog a show can build, so nothing is dropped while a subscriber is connected;
  XPUB tells us when a subscriber joins, and we greet it with a heartbeat at once;
- depth on a PUB socket at ADDR's port + 1 with CONFLATE (one message per subscriber queue: the
  newest wins) and a small kernel send buffer, so a slow link drops old images instead of
  queueing them (queueing is what made the thesis' ROS depth late and lost).

Depth is cropped, downscaled and compressed on a worker thread of its own so the sensor thread
never waits for it; if the worker is still busy when a newer frame comes, the older one is skipped
(counted, reported in heartbeats). Raw depth (the default on loopback) is sent inline instead.
The user label image of a frame (Frame.user_labels, when the backend knows it) goes in its depth
message, made and compressed on the same worker (wire.py: the LABELS flag).
"""
from __future__ import annotations

import os
import re
import threading
import time
from dataclasses import dataclass, replace
from typing import Callable

import numpy as np
import zmq

from backends.network import wire
from host import DepthFrame, Frame, Gesture
from host.errors import UserError

HEARTBEAT_S = 0.5
EVENT_HWM = 1_000_000  # about 9 hours of hands at 30 Hz: in practice never reached
DEPTH_SNDBUF = 256 * 1024
# Codecs that only copy the image (~0.1 ms for 640x480) are sent on the sensor thread, after the
# hands: waking the worker would cost more (it waits for the GIL while the sensor thread makes the
# next frame: up to Python's 5 ms switch interval), and that wait is the subscriber's depth wait.
# The frame's user labels are then made there too (free for `truth`; the engine's, a few ms).
INLINE_CODECS = frozenset({"raw"})

_TCP = re.compile(r"^tcp://(?P<host>[^\s]+):(?P<port>\d{1,5})$")


def endpoints(addr: str) -> tuple[str, str]:
    """ADDR -> (events endpoint, depth endpoint): depth goes to the next port."""
    m = _TCP.match(addr)
    if m is None or not 0 < int(m["port"]) < 65535:
        raise ValueError(f"expected tcp://HOST:PORT such as tcp://127.0.0.1:5555, got {addr!r}")
    return addr, f"tcp://{m['host']}:{int(m['port']) + 1}"


@dataclass(frozen=True)
class DepthOptions:
    """How depth goes on the wire: all of it losslessly by default; less of it on slow links."""

    enabled: bool = True
    codec: str = wire.DEFAULT_CODEC
    downscale: int = 1  # keep every Nth pixel of every Nth row (values stay exact millimetres)
    crop: tuple[int, int, int, int] | None = None  # x, y, width, height in source pixels
    max_fps: float | None = None
    labels: bool = True  # the user label image with each depth image, when the backend knows it

    def shape(self, depth: DepthFrame) -> DepthFrame:
        """Crop, then downscale; the intrinsics follow so mm <-> pixels stays right."""
        data, intr = self.pixels(depth.data), depth.intrinsics
        if self.crop is not None:
            x, y = self.crop[:2]
            intr = replace(intr, cx=intr.cx - x, cy=intr.cy - y)
        if self.downscale > 1:
            k = self.downscale
            intr = replace(intr, fx=intr.fx / k, fy=intr.fy / k, cx=intr.cx / k, cy=intr.cy / k)
        if data is depth.data:
            return depth
        return replace(depth, data=data, intrinsics=intr)

    def pixels(self, image: np.ndarray) -> np.ndarray:
        """The pixels of an image at the depth image's size that are sent (labels go as depth does)."""
        if self.crop is not None:
            x, y, w, h = self.crop
            image = image[y:y + h, x:x + w]
        if self.downscale > 1:
            image = image[::self.downscale, ::self.downscale]
        return image

    def labels_of(self, frame: Frame) -> Callable[[], np.ndarray | None] | None:
        """What makes the frame's labels as sent (called off the sensor thread), or None."""
        if not self.labels or frame.make_user_labels is None:
            return None
        return lambda: None if frame.user_labels is None else self.pixels(frame.user_labels)


class DepthGate:
    """Which frames' depth goes out: none when disabled, else at most `max_fps` images a second."""

    def __init__(self, options: DepthOptions) -> None:
        self.options = options
        self._last = float("-inf")

    def admit(self, frame: Frame) -> bool:
        o = self.options
        if not o.enabled or frame.depth is None:
            return False
        if o.max_fps and frame.capture_time - self._last < 0.95 / o.max_fps:
            return False
        self._last = frame.capture_time
        return True


Labels = Callable[[], np.ndarray | None] | None


class _DepthWorker(threading.Thread):
    """Compresses and sends the newest offered depth image; skips the ones it had no time for."""

    def __init__(self, socket: zmq.Socket, session: int, options: DepthOptions) -> None:
        super().__init__(name="issv-depth-publisher", daemon=True)
        self.socket, self.session, self.options = socket, session, options
        self._cond = threading.Condition()
        self._slot: tuple[int, float, DepthFrame, Labels] | None = None
        self._closing = False
        self.sent = 0
        self.skipped = 0
        self.bytes = 0
        self.raw_bytes = 0
        self.labels_bytes = 0
        self.labels_sent = 0

    def offer(self, frame_seq: int, capture_time: float, depth: DepthFrame, labels: Labels = None) -> None:
        with self._cond:
            if self._slot is not None:
                self.skipped += 1
            self._slot = (frame_seq, capture_time, depth, labels)
            self._cond.notify()

    def run(self) -> None:
        while True:
            with self._cond:
                while self._slot is None and not self._closing:
                    self._cond.wait()
                if self._slot is None:
                    return
                frame_seq, capture, depth, labels = self._slot
                self._slot = None
            self.send(frame_seq, capture, depth, labels)

    def send(self, frame_seq: int, capture_time: float, depth: DepthFrame, labels: Labels = None) -> None:
        """Encode and send one image (on the worker thread, or inline for a codec that only copies)."""
        depth = self.options.shape(depth)
        image = None if labels is None else labels()
        self.sent += 1
        # Step aside between bands: the threads carrying hands and gestures go first.
        msg = wire.encode_depth(self.session, self.sent, capture_time, frame_seq, depth, self.options.codec,
                                pause=os.sched_yield, labels=image)
        self.socket.send(msg, copy=False)
        self.bytes += len(msg)
        self.raw_bytes += depth.data.nbytes
        if image is not None:
            self.labels_sent += 1
            self.labels_bytes += wire.labels_size(msg)

    def close(self) -> None:
        with self._cond:
            self._closing = True
            self._cond.notify()
        self.join(timeout=2.0)


class Publisher:
    """Publishes frames at `bind` (events) and its port + 1 (depth). Call publish() from one thread."""

    def __init__(self, bind: str, depth: DepthOptions = DepthOptions(), backend: str = "") -> None:
        events_addr, depth_addr = endpoints(bind)
        if depth.codec not in wire.CODECS:
            raise UserError(f"issv serve: unknown codec {depth.codec!r}; expected one of {', '.join(wire.CODECS)}")
        self.bind, self.backend, self.depth_options = bind, backend, depth
        self.session = int.from_bytes(os.urandom(8), "little")
        self.ctx = zmq.Context()
        self.events = self.ctx.socket(zmq.XPUB)
        self.events.setsockopt(zmq.SNDHWM, EVENT_HWM)
        self.events.setsockopt(zmq.LINGER, 1000)
        self.depth = self.ctx.socket(zmq.PUB)
        self.depth.setsockopt(zmq.CONFLATE, 1)
        self.depth.setsockopt(zmq.SNDBUF, DEPTH_SNDBUF)
        self.depth.setsockopt(zmq.LINGER, 0)
        for socket, addr in ((self.events, events_addr), (self.depth, depth_addr)):
            try:
                socket.bind(addr)
            except zmq.ZMQError as error:
                self.ctx.destroy(linger=0)
                raise UserError(f"issv serve: cannot bind {addr}: {error} (is another `issv serve` "
                                f"running there? use --bind tcp://HOST:PORT)") from None
        self.seq = {name: 0 for name in wire.STREAMS.values()}
        self.subscribers = 0
        self._lock = threading.Lock()
        self._last_heartbeat = 0.0
        self._depth_gate = DepthGate(depth)
        self._worker = _DepthWorker(self.depth, self.session, depth)
        self._worker.start()
        self._closed = False
        self._last_seq = 0

    # -- per frame (sensor thread) -------------------------------------------------------------
    def _send_gestures(self, gestures: tuple[Gesture, ...], capture_time: float, frame_seq: int) -> None:
        for g in gestures:
            self.seq["gestures"] += 1
            self.events.send(wire.encode_gesture(self.session, self.seq["gestures"], capture_time, frame_seq, g))

    def publish_end(self, gestures: tuple[Gesture, ...]) -> None:
        """Gestures the end of the source completed: sent after the last frame, before the end."""
        with self._lock:
            if not self._closed:
                self._send_gestures(gestures, time.time(), self._last_seq + 1)

    def publish(self, frame: Frame) -> None:
        with self._lock:
            if self._closed:
                return
            self._subscriptions()
            self._send_gestures(frame.gestures, frame.capture_time, frame.seq)
            self._last_seq = frame.seq
            with_depth = self._depth_gate.admit(frame)
            self.seq["hands"] += 1
            self.events.send(wire.encode_hands(self.session, self.seq["hands"], frame.capture_time, frame.seq,
                                               frame.timestamp, frame.backend or self.backend, frame.hands,
                                               with_depth, frame.users))
            labels = self.depth_options.labels_of(frame) if with_depth else None
            if with_depth and self.depth_options.codec in INLINE_CODECS:
                self._worker.send(frame.seq, frame.capture_time, frame.depth, labels)
            elif with_depth:
                self._worker.offer(frame.seq, frame.capture_time, frame.depth, labels)
            if time.monotonic() - self._last_heartbeat >= HEARTBEAT_S:
                self._status(wire.HEARTBEAT)

    def wait_for_subscriber(self, timeout: float) -> bool:
        """Block until a subscriber has joined (benchmarks start counting from there)."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            with self._lock:
                self._subscriptions()
                if self.subscribers:
                    return True
            time.sleep(0.01)
        return False

    def _subscriptions(self) -> None:
        """XPUB hands us b'\\x01topic' when a subscriber joins and b'\\x00topic' when it leaves."""
        while True:
            try:
                note = self.events.recv(zmq.NOBLOCK)
            except zmq.Again:
                return
            if note[:1] == b"\x01":
                self.subscribers += 1
                self._status(wire.HEARTBEAT)  # greet it: it learns our session and sequence numbers
            elif note[:1] == b"\x00":
                self.subscribers = max(0, self.subscribers - 1)

    def _status(self, kind: int) -> None:
        last = dict(self.seq, depth=self._worker.sent)
        self.events.send(wire.encode_status(kind, self.session, 0, last, self.backend, self._worker.skipped,
                                            time.time()))
        self._last_heartbeat = time.monotonic()

    # -- reporting and shutdown ----------------------------------------------------------------
    def stats(self) -> dict:
        w = self._worker
        return {"bind": self.bind, "subscribers": self.subscribers, "sent": dict(self.seq, depth=w.sent),
                "depth_skipped": w.skipped, "depth_bytes": w.bytes, "labels_sent": w.labels_sent,
                "labels_bytes": w.labels_bytes,
                "compression": round(w.raw_bytes / (w.bytes - w.labels_bytes), 2) if w.bytes else None}  # of depth

    def close(self) -> None:
        """Say goodbye (with the last sequence numbers, so subscribers can count tail loss)."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
            self._worker.close()
            self._status(wire.BYE)
            self.events.close(linger=1000)
            self.depth.close(linger=0)
            self.ctx.term()
