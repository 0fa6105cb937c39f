"""Fixtures for osc-in: sessions written from issv's own OSCeleton output, a backend to collect.

The sessions are what the osc effect's OSCeleton preset sends for a scripted performer, written
as Pd qlist text (how the real sessions in ISSV_DATA were recorded), so `issv osc-replay`, Pure
Data's [qlist] and the effect itself can all play them to a real osc-in over UDP.
"""
from __future__ import annotations

import math
import os
import subprocess
import sys
import time
from pathlib import Path

from backends.oscin.backend import OscInBackend, OscInOptions
from effects.osc.coords import Projector
from effects.osc.osceleton import OSCeletonScheme
from host.osc import Message
from host import Frame, Hand, HandState, Side, frames_of

FPS = 30.0
ROOT = Path(__file__).resolve().parents[3]


def hands_at(user: int, i: int, x0: float = 0.0) -> list[Hand]:
    """User `user` at frame i: the left hand circles slowly, the right swipes to the performer's
    right (mirrored: +x) in frames 20-28, 700 mm in 0.27 s."""
    a = i / FPS * math.pi
    left = (x0 - 300 + 60 * math.cos(a), 100 + 60 * math.sin(a), 2000.0)
    k = min(max(i - 20, 0), 8) / 8
    right = (x0 + 100 + 700 * (k * k * (3 - 2 * k)), 250.0, 1700.0)
    return [Hand(1, HandState.TRACKING, left, Side.LEFT, user), Hand(2, HandState.TRACKING, right, Side.RIGHT, user)]


def body_at(user: int, x0: float = 0.0) -> dict[int, dict[str, tuple[float, float, float]]]:
    """The torso and head of user `user` standing at x0 (the preset sends hands only: the
    fixture adds them as OSCeleton would, `/joint torso` and `/joint head`)."""
    return {user: {"torso": (x0, 0.0, 2100.0), "head": (x0, 500.0, 2100.0)}}


def _word(value) -> str:
    return f"{value:.7g}" if isinstance(value, float) else str(value)


def write_session(path: Path, frames: list[list[Hand]], fps: float = FPS,
                  bodies: list[dict] | None = None) -> Path:
    """The OSCeleton preset's messages for these frames (one list of hands each) as a Pd qlist,
    with each frame's body joints ({user: {joint: (x, y, z)}}) in OSCeleton's mapping."""
    scheme = OSCeletonScheme()
    to = Projector("mm", None, (500.0, 4500.0))
    lines = []
    for i, hands in enumerate(frames):
        messages = scheme.frame(Frame(i + 1, 0.0, None, tuple(hands)), list(hands), [], to)
        for user, joints in (bodies[i] if bodies else {}).items():
            messages += [Message("/joint", (("s", name), ("i", user), ("f", (x + 1280) / 2560), ("f", (960 - y) / 1920),
                                            ("f", z / 1280))) for name, (x, y, z) in joints.items()]
        for k, m in enumerate(messages):
            delta = 1000.0 / fps if k == 0 and i > 0 else 0
            lines.append(f"{_word(delta)} osceleton {m.address} {' '.join(_word(v) for _, v in m.args)};")
    path.write_text("\n".join(lines) + "\n")
    return path


def backend(**options) -> OscInBackend:
    """osc-in on a free port, ending 0.6 s after the last message."""
    settings = {"port": 0, "end_after_idle_s": 0.6, "lost_timeout_s": 0.3, **options}
    return OscInBackend(None, OscInOptions.model_validate(settings), warn=lambda text: None)


def collect(b: OscInBackend, first_within_s: float = 60.0) -> list[Frame]:
    """Every frame until the backend ends. Waits for the sender's first datagram first: a sender
    process that starts slowly on a loaded machine must not meet a backend already ended idle."""
    receiver = getattr(b, "receiver", None) or b.inner.receiver  # osc-in, or wrapped for learned gestures
    deadline = time.monotonic() + first_within_s
    while receiver.last_arrival is None and time.monotonic() < deadline:
        time.sleep(0.01)
    return list(frames_of(b))


def env() -> dict:
    return {**os.environ, "PYTHONPATH": str(ROOT)}


def replay(path: Path, port: int, *extra: str) -> subprocess.Popen:
    """`issv osc-replay` in a process of its own."""
    return subprocess.Popen([sys.executable, "-m", "host", "osc-replay", str(path), "--port", str(port), *extra],
                            env=env(), stderr=subprocess.PIPE, text=True)
