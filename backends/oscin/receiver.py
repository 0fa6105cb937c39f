"""The UDP side of `osc-in`: a thread that reads datagrams and hands over complete samples.

Nothing here waits on the show: the thread only decodes, groups a user's joints into samples and
appends them to a deque (thread-safe appends) that the backend drains each frame; gestures are
computed from every sample, so no bridge frame is skipped however slow the show is.

A sample is the joints of one user at one instant: a bundle's joints (OSCeleton sends one bundle
per user per frame), or, for bridges that send loose messages, the joints until one repeats.
Its time is the bundle's time tag when the sender set one, else the arrival time.
"""
from __future__ import annotations

import socket
import threading
import time
from collections import Counter, deque
from dataclasses import dataclass
from typing import Callable

from backends.oscin.decode import IMMEDIATELY, OscError, decode, midnight, seconds_since, time_tag
from backends.oscin.schemes import BadMessage, Reading, Scheme, UserEvent
from host import Joint

Warn = Callable[[str], None]
KEEPALIVE_S = 1.0  # how often bridges that need it (Synapse) are told to keep sending


@dataclass(frozen=True)
class Sample:
    user: int
    joints: dict[str, Joint]
    t: float  # the stream's clock (Receiver.seconds): the sender's time tags, or arrival times
    arrival: float  # time.monotonic() at arrival


@dataclass(frozen=True)
class Announcement:
    event: UserEvent
    t: float
    arrival: float


class Receiver:
    """Listens on `host:port` for one scheme's messages."""

    def __init__(self, scheme: Scheme, host: str, port: int, warn: Warn,
                 keepalive_to: tuple[str, int] | None = None) -> None:
        self.scheme, self.warn, self.keepalive_to = scheme, warn, keepalive_to
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4 << 20)
        try:
            self.sock.bind((host, port))
        except OSError as error:
            self.sock.close()
            raise OSError(f"cannot listen on udp {host}:{port} ({error.strerror}); is another program "
                          f"(or another issv) using that port? Set the option port") from None
        self.port = self.sock.getsockname()[1]
        self.sock.settimeout(0.1)
        self.queue: deque[Sample | Announcement] = deque()
        self.arrived = threading.Event()
        self.datagrams = 0
        self.messages = 0
        self.bad: Counter[str] = Counter()
        self.last_arrival: float | None = None
        self._pending: dict[int, tuple[dict[str, Joint], float]] = {}  # loose messages per user
        self._origin: int | None = None  # midnight before the first message: time 0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name=f"issv-osc-in :{self.port}", daemon=True)

    def start(self) -> None:
        self._thread.start()

    def close(self) -> None:
        self._stop.set()
        self._thread.join(timeout=1.0)
        self.sock.close()

    def _run(self) -> None:
        next_keepalive = 0.0
        while not self._stop.is_set():
            if self.keepalive_to is not None and time.monotonic() >= next_keepalive:
                self._keepalive()
                next_keepalive = time.monotonic() + KEEPALIVE_S
            try:
                data = self.sock.recv(65536)
            except socket.timeout:
                self.flush_loose()
                continue
            except OSError:
                return
            self.receive(data, time.time(), time.monotonic())

    def receive(self, data: bytes, wall: float, arrival: float) -> None:
        """One datagram (public so the bench can time it without a socket)."""
        self.datagrams += 1
        self.last_arrival = arrival
        try:
            messages = decode(data)
        except OscError as error:
            self._bad("datagrams that are not OSC", str(error))
            return
        bundle: dict[int, tuple[dict[str, Joint], float]] = {}
        is_bundle = data.startswith(b"#bundle")
        for tag, address, args in messages:
            self.messages += 1
            t = self._seconds(time_tag(wall) if tag == IMMEDIATELY else tag)
            try:
                events = self.scheme.read(address, args)
            except BadMessage as error:
                self._bad(error.kind, str(error))
                continue
            for event in events:
                if isinstance(event, UserEvent):
                    self._complete(event.user)
                    self.queue.append(Announcement(event, t, arrival))
                elif is_bundle or len(events) > 1:  # one instant: a bundle, or a whole body in one message
                    bundle.setdefault(event.user, ({}, t))[0][event.joint] = Joint(event.position, event.confidence)
                else:
                    self._loose(event, t)
        for user, (joints, t) in bundle.items():
            self._complete(user)
            self.queue.append(Sample(user, joints, t, arrival))
        self.arrived.set()

    def _seconds(self, tag: int) -> float:
        """The stream's clock: the time of day (UTC, seconds since the midnight before the first
        message) of its time tags, or of arrival, to the nanosecond. A sender that stamps its own
        times as a time of day (`issv osc-replay --time-tags`) gets them back exactly
        (decode.seconds_since), so the recogniser sees the sender's clock, not the wire's."""
        if self._origin is None:
            self._origin = midnight(tag)
        return seconds_since(self._origin, tag)

    def _loose(self, reading: Reading, t: float) -> None:
        """A joint sent on its own: a sample ends when one of its joints comes again."""
        pending = self._pending.get(reading.user)
        if pending is not None and reading.joint in pending[0]:
            self._complete(reading.user)
            pending = None
        if pending is None:
            pending = self._pending[reading.user] = ({}, t)
        pending[0][reading.joint] = Joint(reading.position, reading.confidence)

    def _complete(self, user: int) -> None:
        pending = self._pending.pop(user, None)
        if pending is not None:
            self.queue.append(Sample(user, pending[0], pending[1], time.monotonic()))

    def flush_loose(self) -> None:
        """Loose joints waiting for their frame to end: after a quiet spell they are one."""
        for user in list(self._pending):
            self._complete(user)
        if self.queue:
            self.arrived.set()

    def _bad(self, kind: str, detail: str) -> None:
        self.bad[kind] += 1
        if self.bad[kind] == 1:
            self.warn(f"ignoring {kind} (first: {detail}); counted, reported once")

    def _keepalive(self) -> None:
        from host.osc import Message, encode, typed
        for address, args in self.scheme.keepalive():
            try:
                self.sock.sendto(encode(Message(address, tuple(typed(a) for a in args)), True), self.keepalive_to)
            except OSError as error:
                self._bad("keep-alive messages that could not be sent", f"{self.keepalive_to}: {error}")
                return
