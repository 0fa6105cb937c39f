"""The receiving side: sockets in, checked and accounted messages out.

`Accounting` is shared by every transport (ZeroMQ here, ROS in ros.py): per stream it counts what
arrived, what was lost (gaps in the sequence numbers, and the tail the publisher's heartbeats
announce), duplicates, and the capture-to-arrival latency; it notices a publisher restart (a new
session) and says so once; malformed messages are counted per kind and reported once per kind.
Loss counts from the first message a subscriber gets: what was sent before it joined (ZeroMQ's
"slow joiner") was never meant for it. Latency across machines is only as good as the two clocks'
agreement (run NTP or chrony).
"""
from __future__ import annotations

import math
import sys
import time
from array import array
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
import zmq

from backends.network import wire
from backends.network.command import how_to_serve
from backends.network.publisher import endpoints

SILENCE_S = 2.0
BYE_GRACE_S = 0.5  # after a goodbye, how long messages it announced may still take to arrive
Notice = Callable[[str], None]


def stderr_notice(text: str) -> None:
    print(f"issv: network: {text}", file=sys.stderr, flush=True)


@dataclass
class StreamStats:
    """One stream (depth, hands or gestures) of the current and past publisher sessions."""

    received: int = 0
    lost: int = 0
    duplicates: int = 0
    last_seq: int | None = None
    announced: int = 0  # the publisher's last sequence number, from its heartbeats
    latencies_ms: array = field(default_factory=lambda: array("d"))

    def see(self, seq: int, latency_ms: float) -> bool:
        """Account one message; False if it is a duplicate or older than one already seen."""
        if self.last_seq is not None and seq <= self.last_seq:
            self.duplicates += 1
            return False
        if self.last_seq is not None:
            self.lost += seq - self.last_seq - 1
        self.last_seq = seq
        self.received += 1
        self.latencies_ms.append(latency_ms)
        return True

    def tail(self) -> int:
        """Messages announced as sent after the last one that arrived (in flight or lost)."""
        if self.last_seq is None:
            return 0
        return max(0, self.announced - self.last_seq)

    def close_session(self) -> None:
        """The publisher went away: what it announced and we never got is lost."""
        self.lost += self.tail()
        self.last_seq, self.announced = None, 0

    def to_json(self) -> dict:
        lost = self.lost + self.tail()
        data = np.frombuffer(self.latencies_ms, dtype=np.float64)
        latency = ({k: round(float(v), 3) for k, v in zip(("p50", "p99"), np.percentile(data, [50, 99]))}
                   if data.size else {"p50": None, "p99": None})
        total = self.received + lost
        return {"received": self.received, "lost": lost, "loss_pct": round(100.0 * lost / total, 3) if total else 0.0,
                "duplicates": self.duplicates, "latency_ms": latency}


class Accounting:
    """Sessions, sequence numbers, latency, malformed messages: the same for every transport."""

    def __init__(self, where: str, notice: Notice = stderr_notice, start: str = "") -> None:
        self.where = where
        self.notice = notice
        self.start = start  # where and how to start the publisher awaited (said while none is heard)
        self.streams = {name: StreamStats() for name in wire.STREAMS.values()}
        self.malformed: dict[str, int] = {}
        self.session: int | None = None
        self._retired: set[int] = set()
        self.restarts = 0
        self.stale = 0
        self.last_message = time.monotonic()
        self._silent = False
        self._lost_said: set[str] = set()
        self.ended_at: float | None = None  # when the publisher said goodbye (time.monotonic())

    def bad(self, error: wire.WireError) -> None:
        n = self.malformed.get(error.kind, 0)
        self.malformed[error.kind] = n + 1
        if n == 0:
            self.notice(f"ignored a malformed message from {self.where} ({error}); "
                        f"further `{error.kind}` messages are counted, not reported")

    def accept(self, msg: wire.Message, arrived: float | None = None) -> bool:
        """True if `msg` is new and from the current publisher session; `arrived` is time.time()."""
        h = msg.header
        now_mono = time.monotonic()
        if h.session in self._retired:
            self.stale += 1
            return False
        first = self.session is None
        if h.session != self.session:
            if self.session is not None:
                self._retired.add(self.session)
                self.restarts += 1
                for s in self.streams.values():
                    s.close_session()
                self.notice(f"publisher at {self.where} restarted; receiving from its new run")
                self._silent = False  # one message says it all
            self.session = h.session
            self.ended_at = None
        if self._silent:
            self.notice(f"publisher at {self.where} found; receiving" if first else f"{self.where} is sending again")
            self._silent = False
        self.last_message = now_mono
        if isinstance(msg, wire.StatusMsg):
            for name, last in msg.last.items():
                self.streams[name].announced = max(self.streams[name].announced, last)
            if msg.header.kind == wire.BYE:
                self.ended_at = now_mono
                self.notice(f"publisher at {self.where} ended its show; waiting for it to come back")
            return True
        name = wire.STREAMS[h.kind]
        stream = self.streams[name]
        fresh = stream.see(h.seq, ((arrived or time.time()) - h.capture_time) * 1000.0)
        if fresh and stream.lost and name not in self._lost_said:
            self._lost_said.add(name)
            why = " (newest wins under congestion)" if name == "depth" else ""
            self.notice(f"{name}: messages lost{why}; totals in the summary at exit")
        return fresh

    @property
    def ended(self) -> bool:
        """The publisher said goodbye (and has not started again)."""
        return self.ended_at is not None

    def settled(self) -> bool:
        """After the goodbye: has every message it announced arrived, or BYE_GRACE_S passed (the rest
        is lost)? Over ROS each topic is a connection of its own, so the goodbye on the status topic
        may overtake the last hands and depth (one hands message was counted lost so)."""
        return (all(s.tail() == 0 for s in self.streams.values())
                or self.ended_at is not None and time.monotonic() - self.ended_at >= BYE_GRACE_S)

    def waiting(self) -> str | None:
        """Until a publisher is heard: where one is awaited and how to start it; then None."""
        if self.session is not None:
            return None
        return f"no publisher at {self.where} yet" + (f" (start one {self.start})" if self.start else "")

    def check_silence(self) -> None:
        if not self._silent and not self.ended and time.monotonic() - self.last_message > SILENCE_S:
            self._silent = True
            waiting = self.waiting()
            self.notice(f"{waiting}; the show waits for it" if waiting else
                        f"nothing from {self.where} for {SILENCE_S:.0f} s; waiting (reconnection is automatic)")

    def to_json(self) -> dict:
        return {"where": self.where, "streams": {k: v.to_json() for k, v in self.streams.items()},
                "malformed": dict(self.malformed), "restarts": self.restarts, "stale": self.stale}

    def summary(self) -> str:
        parts = []
        for name, s in self.to_json()["streams"].items():
            lat = s["latency_ms"]
            timing = f", latency p50 {lat['p50']:.1f} ms p99 {lat['p99']:.1f} ms" if s["received"] else ""
            parts.append(f"{name} {s['received']} received, {s['lost']} lost ({s['loss_pct']:.1f} %){timing}")
        bad = ", ".join(f"{k} {v}" for k, v in sorted(self.malformed.items())) or "none"
        return f"from {self.where}: " + "; ".join(parts) + f"; malformed: {bad}; restarts: {self.restarts}"


class ZmqSubscriber:
    """Connects to an `issv serve` at ADDR (events) and ADDR's port + 1 (depth, if wanted)."""

    def __init__(self, connect: str, depth: bool = True, notice: Notice = stderr_notice) -> None:
        events_addr, depth_addr = endpoints(connect)
        self.accounting = Accounting(connect, notice, how_to_serve(connect))
        self.ctx = zmq.Context()
        self.events = self._socket(events_addr, conflate=False, max_size=wire.MAX_JSON + wire.HEADER.size)
        self.depth = self._socket(depth_addr, conflate=True, max_size=64 << 20) if depth else None
        self.poller = zmq.Poller()
        for s in (self.events, self.depth):
            if s is not None:
                self.poller.register(s, zmq.POLLIN)

    def _socket(self, addr: str, conflate: bool, max_size: int) -> zmq.Socket:
        s = self.ctx.socket(zmq.SUB)
        s.setsockopt(zmq.LINGER, 0)
        s.setsockopt(zmq.MAXMSGSIZE, max_size)  # a hostile sender cannot make us allocate more
        s.setsockopt(zmq.RECONNECT_IVL, 100)
        s.setsockopt(zmq.RECONNECT_IVL_MAX, 1000)
        if conflate:
            s.setsockopt(zmq.CONFLATE, 1)
        else:
            s.setsockopt(zmq.RCVHWM, 1_000_000)
        s.setsockopt(zmq.SUBSCRIBE, b"")
        s.connect(addr)
        return s

    def poll(self, timeout_ms: float) -> list[wire.Message]:
        """Messages that arrived within `timeout_ms`: events first (in order), then depth."""
        ready = dict(self.poller.poll(max(0, math.ceil(timeout_ms))))
        out: list[wire.Message] = []
        for socket in (self.events, self.depth):
            if socket is None or socket not in ready:
                continue
            while True:
                try:
                    parts = socket.recv_multipart(zmq.NOBLOCK, copy=True)
                except zmq.Again:
                    break
                msg = self._decode(parts)
                if msg is not None and self.accounting.accept(msg):
                    out.append(msg)
        self.accounting.check_silence()
        return out

    def _decode(self, parts: list[bytes]) -> wire.Message | None:
        try:
            if len(parts) != 1:
                raise wire.WireError("multipart", f"{len(parts)} parts, expected 1")
            return wire.decode(parts[0])
        except wire.WireError as error:
            self.accounting.bad(error)
        except Exception as error:  # a security boundary: nothing a sender does may crash the show
            self.accounting.bad(wire.WireError("undecodable", f"{type(error).__name__}: {error}"))
        return None

    def close(self) -> None:
        self.ctx.destroy(linger=0)
