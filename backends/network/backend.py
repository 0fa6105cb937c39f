"""`network`: frames from a remote `issv serve`, so effects cannot tell they came over a wire.

A frame is rebuilt from the publisher's hands message (one per publisher frame, sent reliably) and
the gesture events that came before it on the same ordered channel; its depth is the newest image
received. A frame waits at most `depth_wait_ms` for its own depth image, and never once the next
frame's hands are in: depth is newest-wins, hands and gestures are never held back for long.
The user label image travels with its depth image (in the same ZeroMQ message; on ROS a topic of
its own, matched by capture time) and becomes the frame's `user_labels`.
"""
from __future__ import annotations

import sys
import threading
import time
from collections import OrderedDict, deque
from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationInfo, field_validator

from backends.network import wire
from backends.network.publisher import endpoints
from host import Backend, DepthFrame, Frame, Gesture, PluginUnavailable, Update
from host.errors import UserError

POLL_MS = 100
LOOSE_LABELS = 8  # ROS label images kept while their depth image has not come (or was skipped)


class NetworkOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    transport: Literal["zmq", "ros"] = "zmq"
    connect: str = "tcp://127.0.0.1:5555"  # with transport = "ros": the master URI (default $ROS_MASTER_URI)
    depth: bool = True  # false: hands and gestures only (the depth connection is not even opened)
    depth_wait_ms: float = Field(40.0, ge=0, le=1000)  # how long a frame may wait for its own depth image
    end_with_publisher: bool = False  # true: the show ends when the publisher says goodbye
    namespace: str = "/openiss"  # ROS topic namespace
    ros_depth: Literal["frame", "image"] = "frame"  # ROS depth topic: openiss/DepthFrame or sensor_msgs/Image

    @field_validator("connect")
    @classmethod
    def _address(cls, value: str, info: ValidationInfo) -> str:
        if info.data.get("transport") == "zmq":
            try:
                endpoints(value)
            except ValueError:
                raise ValueError("expected tcp://HOST:PORT such as tcp://127.0.0.1:5555 "
                                 "(depth uses PORT + 1)") from None
        return value


class NetworkBackend(Backend):
    """Subscribes to `connect` (ZeroMQ, or a ROS master with transport = "ros")."""

    name = "network"
    Options = NetworkOptions
    needs_source = False

    @classmethod
    def availability(cls) -> str | None:
        try:
            import zmq  # noqa: F401
        except ImportError:
            return "pyzmq is not installed: pip install pyzmq"
        return None

    def init(self) -> None:
        o = self.options
        if o.transport == "ros":
            from backends.network.ros import RosSubscriber
            try:
                self.transport = RosSubscriber(o.connect, o.namespace, depth=o.depth, depth_topic=o.ros_depth)
            except PluginUnavailable as error:
                raise UserError(f"backend 'network' (transport = \"ros\"): {error}") from None
        else:
            from backends.network.subscriber import ZmqSubscriber
            self.transport = ZmqSubscriber(o.connect, depth=o.depth)
        self.accounting = self.transport.accounting
        self._hands: deque[tuple[float, wire.HandsMsg]] = deque()  # (arrival, message)
        self._gestures: list[Gesture] = []
        self._depth: DepthFrame | None = None
        self._depth_seq = -1
        self._depth_session: int | None = None
        self._labels: np.ndarray | None = None  # the user labels of self._depth
        self._loose: OrderedDict[tuple[int, float], np.ndarray] = OrderedDict()
        self._labels_session: int | None = None  # a session whose labels travel apart (ROS): wait for them
        self._seq = 0
        self._backend = ""
        self._stopping = threading.Event()
        self._busy = threading.Lock()

    def update(self) -> Update:
        """The next frame; False after a poll that brought nothing (no publisher yet, or a silent
        one), so the host keeps its time limits and stop requests; None once stopped, or with
        end_with_publisher once the publisher said goodbye."""
        with self._busy:
            while not self._stopping.is_set():
                frame = self._ready()
                if frame is not None:
                    return frame
                if self.accounting.ended and self.options.end_with_publisher and self.accounting.settled():
                    return self._flush()
                messages = self.transport.poll(self._wait_ms())
                if not messages and not self._hands:
                    return False
                for msg in messages:
                    self._take(msg)
            return None

    def input_label(self) -> str:
        """The status line's, HUD's and summary's input: the publisher, or where one is awaited."""
        accounting = getattr(self, "accounting", None)
        if accounting is None:
            return f"{self.options.connect} (not connected yet)"
        return accounting.waiting() or f"publisher at {accounting.where}"

    def _take(self, msg: wire.Message) -> None:
        if isinstance(msg, wire.DepthMsg):
            if msg.frame_seq > self._depth_seq or msg.header.session != self._depth_session:
                self._depth, self._depth_seq = msg.depth, msg.frame_seq
                self._depth_session = msg.header.session
                key = (msg.header.session, msg.header.capture_time)
                self._labels = msg.labels if msg.labels is not None else self._loose.pop(key, None)
        elif isinstance(msg, wire.LabelsMsg):
            self._labels_session = msg.header.session
            if (msg.header.session, msg.header.capture_time) == self._depth_key():
                self._labels = msg.labels
            else:
                self._loose[(msg.header.session, msg.header.capture_time)] = msg.labels
                while len(self._loose) > LOOSE_LABELS:
                    self._loose.popitem(last=False)
        elif isinstance(msg, wire.GestureMsg):
            self._gestures.append(msg.gesture)
        elif isinstance(msg, wire.HandsMsg):
            self._hands.append((time.monotonic(), msg))

    def _depth_key(self) -> tuple[int, float] | None:
        return None if self._depth is None else (self._depth_session, self._depth.capture_time)

    def _wait_ms(self) -> float:
        if not self._hands:
            return POLL_MS
        arrival = self._hands[0][0]
        return max(0.0, min(POLL_MS, (arrival + self.options.depth_wait_ms / 1000 - time.monotonic()) * 1000))

    def _ready(self) -> Frame | None:
        """The oldest waiting frame, if its depth is in, it waited long enough, or a newer one came."""
        if not self._hands:
            return None
        arrival, head = self._hands[0]
        has_depth = (not head.depth or not self.options.depth
                     or (self._depth_seq >= head.frame_seq and self._depth_session == head.header.session
                         and (self._labels is not None or self._labels_session != head.header.session)))
        waited = time.monotonic() - arrival >= self.options.depth_wait_ms / 1000
        if not (has_depth or waited or len(self._hands) > 1):
            return None
        return self._oldest()

    def _oldest(self) -> Frame:
        """The oldest waiting hands message as a frame, named after the backend that made it."""
        _, head = self._hands.popleft()
        self._backend = head.backend
        return self._frame(head.header.capture_time, head.hands, head.users)

    def _frame(self, capture_time: float, hands, users=()) -> Frame:
        gestures, self._gestures = tuple(self._gestures), []
        self._seq += 1
        labels = self._labels
        return Frame(self._seq, capture_time, self._depth, tuple(hands) if self.tracking_hands else (),
                     gestures if self.detecting_gestures else (), self._backend, users=tuple(users),
                     make_user_labels=None if labels is None else lambda: labels)

    def _flush(self) -> Frame | None:
        """The publisher ended: deliver what is still waiting, then end the stream."""
        if self._hands:
            return self._oldest()
        if self._gestures:
            return self._frame(time.time(), ())
        return None

    def stats(self) -> dict:
        """Loss, latency and malformed messages per stream (also printed at stop)."""
        return self.accounting.to_json()

    def world_to_depth(self, position):
        if self._depth is None:
            raise PluginUnavailable("backend 'network' has received no depth image yet to project into")
        return self._depth.world_to_depth(position)

    def stop(self) -> None:
        super().stop()
        transport = getattr(self, "transport", None)
        if transport is None:
            return
        self._stopping.set()
        with self._busy:
            transport.close()
            self.transport = None
        print(f"issv: network: {self.accounting.summary()}", file=sys.stderr, flush=True)
