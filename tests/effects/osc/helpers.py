"""Real sockets, real receivers (Pure Data, oscdump) and a scripted performer for the OSC tests.

The performer is an in-process Source whose frames carry ground truth; the real `truth` backend
turns it into hands and gestures, and the real Show loop drives the `osc` effect: everything
but the depth camera is the production path.
"""
from __future__ import annotations

import math
import shutil
import socket
import subprocess
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
import pytest
from pythonosc.parsing.osc_types import get_string
from pythonosc.osc_message import OscMessage
from pythonosc.osc_bundle import OscBundle

from backends.truth import TruthBackend
from bench.osc import PATCH as PD_PATCH, UdpInbox, free_port, pd_command
from effects.osc import OscEffect
from effects.osc.destinations import warn_stderr
from host import (Backend, DepthFrame, Frame, Hand, HandState, Intrinsics, Joint, Side, Source, Stage, Truth,
                  TruthGesture, User)
from host.loop import EffectSlot, Limits, PacedSource, Show

ROOT = Path(__file__).resolve().parents[3]
K = Intrinsics.from_fov(640, 480, 57, 43)
FPS = 30.0


def as_sent(args: list) -> list:
    """What Pd echoes back of `args`: strings exactly, numbers as 32-bit floats (pytest 9.2's approx
    refuses a list with strings in it)."""
    return [a if isinstance(a, str) else pytest.approx(a, rel=1e-7) for a in args]


def hand_at(side: Side, i: int) -> tuple[float, float, float]:
    """Where the scripted performer's hand is at frame i: both hands circle at 2 m."""
    sign = 1 if side is Side.RIGHT else -1
    a = i / FPS * 2 * math.pi * 0.5
    return (sign * (250.0 + 100 * math.cos(a)), 100 * math.sin(a) + 50.0 * sign, 2000.0 + 10 * i)


@dataclass
class Script:
    """Frames 1..n; `hands` gives which sides are visible at a frame; gestures by frame interval."""

    n: int = 30
    hands: Callable[[int], tuple[Side, ...]] = lambda i: (Side.LEFT, Side.RIGHT)
    gestures: tuple[TruthGesture, ...] = (TruthGesture("wave", Side.RIGHT, 5 / FPS, 9 / FPS),
                                          TruthGesture("swipe_left", Side.LEFT, 15 / FPS, 18 / FPS))


class ScriptedSource(Source):
    """A depth source made in-process (no camera here): a blank 640x480 image with ground truth."""

    name = "scripted"

    def __init__(self, script: Script) -> None:
        super().__init__()
        self.script, self.fps, self.intrinsics, self.i = script, FPS, K, 0
        self.blank = np.zeros((480, 640), np.uint16)

    def read(self) -> DepthFrame | None:
        if self.i >= self.script.n:
            return None
        i, self.i = self.i, self.i + 1
        t = i / FPS
        truth = Truth(hands={s: hand_at(s, i) for s in self.script.hands(i)},
                      gestures=tuple(g for g in self.script.gestures if g.start <= t < g.end))
        return DepthFrame(self.blank, K, i, t, truth=truth)


def make_osc(warn=warn_stderr, **options) -> OscEffect:
    """The `osc` effect with options validated as a profile's would be."""
    return OscEffect(OscEffect.Options.model_validate(options), warn=warn)


def run_show(effects, script: Script | None = None, realtime: bool = False, fps: float = 240.0,
             stage: Stage | None = None) -> Show:
    """One show, start to end, on the real loop: scripted source -> truth backend -> effects."""
    backend = TruthBackend(PacedSource(ScriptedSource(script or Script()), realtime))
    slots = [EffectSlot(e, f"effects[{k}]") for k, e in enumerate(effects)]
    show = Show(backend, slots, stage or Stage((1280, 720), fps, backend.name), limits=Limits())
    show.run()
    return show


@dataclass
class Packet:
    """One received datagram, decoded: its messages as (address, type tags, arguments)."""

    at: float
    bundle: bool
    messages: list[tuple[str, str, list]]


def decode(data: bytes) -> tuple[bool, list[tuple[str, str, list]]]:
    def one(dgram: bytes):
        address, index = get_string(dgram, 0)
        tags, _ = get_string(dgram, index)
        return address, tags.lstrip(","), OscMessage(dgram).params

    if OscBundle.dgram_is_bundle(data):
        return True, [one(m.dgram) for m in OscBundle(data)]
    return False, [one(data)]


class Receiver(UdpInbox):
    """A UDP socket on an ephemeral port that records every datagram on a thread."""

    def __init__(self) -> None:
        self.packets: list[Packet] = []
        super().__init__()

    @property
    def address(self) -> str:
        return f"127.0.0.1:{self.port}"

    def handle(self, data: bytes, at: float) -> None:
        self.packets.append(Packet(at, *decode(data)))

    def wait_for(self, predicate, timeout: float = 5.0) -> bool:
        deadline = time.time() + timeout
        while time.time() < deadline:
            if predicate(self):
                return True
            time.sleep(0.01)
        return predicate(self)

    def wait_quiet(self, quiet_s: float = 0.3, timeout: float = 5.0) -> bool:
        """Whether datagrams came and then stopped for `quiet_s`: after a show, all of them are in
        (this thread may lag behind the sender when the machine is busy)."""
        return self.wait_for(lambda r: bool(r.packets) and time.time() - r.packets[-1].at >= quiet_s, timeout)

    def has_frame(self, seq: int, address: str = "/issv/frame") -> bool:
        """Whether the bundle of frame `seq` arrived (the last one of a show: all before it did)."""
        return any(m[2][0] == seq for m in self.messages(address))

    def messages(self, address: str | None = None) -> list[tuple[str, str, list]]:
        return [m for p in list(self.packets) for m in p.messages if address is None or m[0] == address]


class PureData:
    """`pd -nogui` running a patch (default patches/issv-receiver.pd), listening on `port`, echoing to `echo`."""

    def __init__(self, echo: Receiver, patch: Path = PD_PATCH, sends: tuple[str, ...] = ()) -> None:
        if shutil.which("pd") is None:
            raise RuntimeError("Pure Data is not installed: apt-get install puredata-core (scripts/setup.sh does)")
        self.port = free_port()
        self.echo = echo
        extra = [arg for text in sends for arg in ("-send", text)]  # more `pd -send` messages for the patch
        self.proc = subprocess.Popen(pd_command(self.port, echo.port, patch) + extra, stdout=subprocess.DEVNULL,
                                     stderr=subprocess.PIPE, text=True)
        if not echo.wait_for(lambda r: r.messages("/echo/ready"), timeout=10):
            self.close()
            raise RuntimeError(f"Pure Data did not start the patch: {self.stderr}")

    @property
    def address(self) -> str:
        return f"127.0.0.1:{self.port}"

    def close(self) -> str:
        if self.proc.poll() is None:
            self.proc.terminate()
        try:
            _, err = self.proc.communicate(timeout=5)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            _, err = self.proc.communicate()
        self.stderr = err
        return err


class OscDump:
    """liblo's `oscdump -L PORT`: its decoded lines (TIMETAG ADDRESS TYPES ARGS...)."""

    def __init__(self) -> None:
        if shutil.which("oscdump") is None:
            raise RuntimeError("oscdump is not installed: apt-get install liblo-tools (scripts/setup.sh does)")
        self.port = free_port()
        self.proc = subprocess.Popen(["oscdump", "-L", str(self.port)], stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, text=True)
        self.lines: list[list[str]] = []
        threading.Thread(target=self._read, daemon=True).start()
        probe = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        deadline = time.time() + 10
        while not self.lines and time.time() < deadline:  # oscdump says nothing when it is ready
            probe.sendto(b"/probe\0\0,\0\0\0", ("127.0.0.1", self.port))
            time.sleep(0.05)
        probe.close()
        if not self.lines:
            raise RuntimeError(f"oscdump did not start on port {self.port}")

    def _read(self) -> None:
        for line in self.proc.stdout:
            if line.strip():
                self.lines.append(line.split())

    @property
    def address(self) -> str:
        return f"127.0.0.1:{self.port}"

    def stop(self, expect: int = 0, until=lambda lines: True) -> list[list[str]]:
        """The decoded lines after the probes, once `expect` of them arrived and `until(lines)`
        holds (or 5 s passed)."""
        deadline = time.time() + 5
        while not (len(self._data()) >= expect and until(self._data())) and time.time() < deadline:
            time.sleep(0.02)
        self.proc.terminate()
        self.proc.wait(timeout=5)
        return self._data()

    def _data(self) -> list[list[str]]:
        return [line for line in list(self.lines) if line[1] != "/probe"]


# -- performers with bodies (backends that report users) ------------------------------------------
#: A standing performer's joints relative to where it stands (mm; +x is the performer's right).
BODY = {"head": (0, 650, 0), "neck": (0, 450, 0), "torso": (0, 200, 0),
        "left_shoulder": (-180, 430, 0), "left_elbow": (-300, 250, 0), "left_hand": (-320, 0, -20),
        "right_shoulder": (180, 430, 0), "right_elbow": (300, 250, 0), "right_hand": (320, 0, -20),
        "left_hip": (-110, -50, 0), "right_hip": (110, -50, 0)}


def body_at(x0: float, i: int, raised: bool = False) -> dict[str, Joint]:
    """The joints of a performer standing at x0, 2.2 m away, at frame i: the right hand rests at
    the side, or (raised) sticks out forwards and up, moving a little each frame."""
    joints = {name: Joint((x0 + x, y, 2200.0 + z)) for name, (x, y, z) in BODY.items()}
    if raised:
        joints["right_hand"] = Joint((x0 + 250, 450 + 2 * i, 1750.0))
    return joints


class UsersBackend(Backend):
    """Frames with users, made in-process (a backend that reports users, as osc-in and the open
    engine do): `users(i)` gives frame i's users, each user's hands follow from its joints."""

    name = "scripted-users"
    needs_source = False

    def __init__(self, users: Callable[[int], tuple[User, ...]], n: int, fps: float = FPS) -> None:
        super().__init__(None, None)
        self.users, self.n, self.fps, self.i = users, n, fps, 0

    def update(self) -> Frame | None:
        if self.i >= self.n:
            return None
        if self.i:
            time.sleep(1 / self.fps)
        i, self.i = self.i, self.i + 1
        users = self.users(i)
        hands = tuple(Hand(10 * u.id + k, HandState.TRACKING, u.joints[name].position, side, u.id)
                      for u in users if u.in_view
                      for k, (name, side) in enumerate((("left_hand", Side.LEFT), ("right_hand", Side.RIGHT)), 1)
                      if name in u.joints)
        return Frame(i + 1, time.time(), None, hands, backend=self.name, users=users, time=i / self.fps)


def run_users(effects, users: Callable[[int], tuple[User, ...]], n: int) -> Show:
    """One show on the real loop with frames that carry users, at 30 frames a second."""
    return run_show_with(UsersBackend(users, n), effects)


def run_show_with(backend: Backend, effects) -> Show:
    """One show on the real loop: this backend's frames to these effects."""
    slots = [EffectSlot(e, f"effects[{k}]") for k, e in enumerate(effects)]
    show = Show(backend, slots, Stage((1280, 720), FPS, backend.name), limits=Limits())
    show.run()
    return show
