"""Reading a teaching example: a hand-trajectory CSV, a depth clip (.npz) or an MCAP recording,
optionally cut to a window (`take.csv@3.5-6.0`, seconds of the file's own clock)."""
from __future__ import annotations

import re
from pathlib import Path
from typing import Iterator, Mapping, Sequence

from host.errors import UserError
from host.learned.features import performer_body, postures
from host.learned.learner import Take
from host.model import Hand

_WINDOW = re.compile(r"^(?P<path>.+)@(?P<start>\d+(?:\.\d*)?)?-(?P<end>\d+(?:\.\d*)?)?$")
KINDS = (".csv", ".npz", ".mcap")


def parse_example(text: str) -> tuple[Path, float, float]:
    """`FILE` or `FILE@START-END` (either end may be left out) -> (path, start, end)."""
    match = _WINDOW.match(text)
    if not match:
        return Path(text), 0.0, float("inf")
    start = float(match["start"]) if match["start"] else 0.0
    end = float(match["end"]) if match["end"] else float("inf")
    if end <= start:
        raise UserError(f"{text}: the window @START-END must end after it starts (seconds, e.g. take.csv@3.5-6.0)")
    return Path(match["path"]), start, end


Frames = Iterator[tuple[float, Sequence[Hand], Mapping]]


def _csv(path: Path, mirrored: bool) -> tuple[Frames, bool]:
    from host.commands.gestures import read_trajectories
    return ((f.t, f.hands, f.body) for f in read_trajectories(path)), mirrored


def _clip(path: Path, backend: str) -> tuple[Frames, bool]:
    """A depth clip through a backend's tracker: its hands, measured against its performer's torso
    and head when it reports users (the open engine does), as the show measures them."""
    from host.app import plugin_class
    source_cls, backend_cls = plugin_class("sources", "clip"), plugin_class("backends", backend)
    tracked = []
    mirrored = True
    with backend_cls(source_cls(source_cls.Options(path=str(path))), backend_cls.Options()) as tracker:
        while (frame := tracker.update()) is not None:
            if frame.depth is not None:
                mirrored = frame.depth.mirrored
            tracked.append((frame.timestamp, frame.hands, performer_body(frame)))
    return iter(tracked), mirrored


def _recording(path: Path, mirrored: bool) -> tuple[Frames, bool]:
    from host.recording.reader import Recording
    out = []
    with Recording(path) as recording:
        for frame in recording.frames():
            if frame.depth is not None:
                mirrored = frame.depth.mirrored
            out.append((frame.timestamp if frame.depth is not None else frame.capture_time, frame.hands,
                        performer_body(frame)))
    return iter(out), mirrored


def read_take(text: str, mirrored: bool, backend: str = "openiss") -> Take:
    """One example as postures; UserError naming the file when it cannot be read or holds no hands."""
    path, start, end = parse_example(text)
    if not path.exists():
        raise UserError(f"{path}: no such example (a .csv trajectory, .npz depth clip or .mcap recording)")
    kind = path.suffix.lower()
    if kind == ".csv":
        frames, mirrored = _csv(path, mirrored)
    elif kind == ".npz":
        frames, mirrored = _clip(path, backend)
    elif kind == ".mcap":
        frames, mirrored = _recording(path, mirrored)
    else:
        raise UserError(f"{path}: cannot learn from a {kind or 'file without extension'}; "
                        f"expected one of {', '.join(KINDS)}, or a whole learned-gesture .json")
    t, p = postures(((ft, h, b) for ft, h, b in frames if start <= ft <= end), mirrored)
    if len(t) < 3:
        raise UserError(f"{text}: no stretch with both hands seen in it; nothing to learn from")
    return Take(text, t, p)
