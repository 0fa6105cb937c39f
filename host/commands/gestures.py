"""`issv gestures FILE.csv`: run a backend's gesture recogniser on a hand-trajectory file.

The trajectory format is docs/architecture.md's: header `t,hand,x,y,z`; t in seconds, hand an integer id
or `left` / `right`, x, y, z in millimetres; rows whose hand is `torso` or `head` are body
reference points. Rows with the same t form one frame. Prints one event line per gesture.

The backend capability used here is declared in host/contracts.py: `Backend.recognizer`, a class
method returning a Recognizer (`update(t, hands, body, mirrored)`, `finish()` at the end of the
stream); backends without one leave it None.
"""
from __future__ import annotations

import argparse
import csv
import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterator

from host.errors import UserError
from host.learned.features import BODY
from host.learned.recognizer import LearnedRecognizer
from host.model import Hand, HandState, Side, Vec3
from host.plugins import default_registry

HELP = "print the gesture events a backend's recogniser finds in a hand-trajectory CSV (t,hand,x,y,z)"
COLUMNS = ("t", "hand", "x", "y", "z")
NAMED_HANDS = {"left": (1, Side.LEFT), "right": (2, Side.RIGHT)}  # id and side of a named hand


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("file", type=Path, help="hand-trajectory CSV: header t,hand,x,y,z (docs/architecture.md)")
    p.add_argument("--backend", default="openiss", help="backend whose recogniser to run (default: openiss)")
    p.add_argument("--mirrored", action="store_true",
                   help="the coordinates come from a mirrored image: +x is the performer's right")
    add_learned_argument(p)


def add_learned_argument(p: argparse.ArgumentParser) -> None:
    p.add_argument("--learned", action="append", type=Path, default=[], metavar="FILE",
                   help="also recognise this learned gesture (made by `issv learn`; repeatable)")


@dataclass
class TrajectoryFrame:
    """The rows of one instant: hands and body reference points (mm)."""

    t: float
    hands: list[Hand] = field(default_factory=list)
    body: dict[str, Vec3] = field(default_factory=dict)


def read_trajectories(path: Path) -> Iterator[TrajectoryFrame]:
    """The file's frames in order; raises UserError naming the file and line of any bad row."""
    try:
        handle = path.open(newline="")
    except OSError as error:
        raise UserError(f"{path}: cannot read the trajectory file ({error.strerror})") from None
    with handle:
        try:
            yield from _frames(path, csv.DictReader(handle))
        except (UnicodeDecodeError, csv.Error) as error:
            raise UserError(f"{path}: not a text CSV of t,hand,x,y,z rows ({error})") from None


def _frames(path: Path, reader: csv.DictReader) -> Iterator[TrajectoryFrame]:
    """The rows of `reader` grouped by instant; bad rows raise UserError naming the line."""
    missing = [c for c in COLUMNS if c not in (reader.fieldnames or [])]
    if missing:
        raise UserError(f"{path}:1: the header lacks {', '.join(missing)}; "
                        f"expected {','.join(COLUMNS)} (docs/architecture.md, Hand trajectories)")
    frame: TrajectoryFrame | None = None
    for row in reader:
        line = reader.line_num
        parsed = _row(path, line, row)
        if parsed is None:
            continue
        t, name, position = parsed
        if frame is not None and t < frame.t:
            raise UserError(f"{path}:{line}: t goes back in time ({t} after {frame.t}); sort the rows by t")
        if frame is None or t != frame.t:
            if frame is not None:
                yield frame
            frame = TrajectoryFrame(t)
        if position is None:
            continue  # an unknown position: the hand is not seen at this instant
        if name in BODY:
            frame.body[name] = position
        else:
            hand_id, side = _hand(path, line, name)
            frame.hands.append(Hand(hand_id, HandState.TRACKING, position, side))
    if frame is not None:
        yield frame


def _row(path: Path, line: int, row: dict) -> tuple[float, str, Vec3 | None] | None:
    """A row's time, point name and position (None where unknown); None for a blank row."""
    if not any((v or "").strip() for v in row.values()):
        return None
    t, x, y, z = (_number(path, line, row, c) for c in ("t", "x", "y", "z"))
    if not math.isfinite(t):
        raise UserError(f"{path}:{line}: t must be a finite number of seconds, got {row['t']!r}")
    position = (x, y, z) if all(math.isfinite(c) for c in (x, y, z)) else None
    return t, (row["hand"] or "").strip().lower(), position


def _number(path: Path, line: int, row: dict, column: str) -> float:
    text = (row.get(column) or "").strip()
    try:
        return float(text)
    except ValueError:
        raise UserError(f"{path}:{line}: column {column} must be a number, got {text!r}") from None


def _hand(path: Path, line: int, name: str) -> tuple[int, Side]:
    """An integer id as it is (side unknown); `left` and `right` are hands 1 and 2 with their side."""
    if name.lstrip("-").isdigit():
        return int(name), Side.UNKNOWN
    if name not in NAMED_HANDS:
        raise UserError(f"{path}:{line}: hand must be an integer id, left, right, torso or head; got {name!r}")
    return NAMED_HANDS[name]


def recognizer_for(backend: str):
    """The named backend's recogniser, or a UserError saying which backends have one."""
    registry = default_registry()
    entry = registry.get("backends", backend)
    able = [r.name for r in registry.all("backends") if r.cls.recognizer is not None]
    if entry is None:
        raise UserError(f"no backend named {backend!r}; backends with a recogniser: {', '.join(able) or 'none'}")
    if entry.cls.recognizer is None:
        raise UserError(f"backend {backend!r} has no recogniser that runs on hand trajectories; "
                        f"use one of: {', '.join(able) or 'none installed'}")
    return entry.cls.recognizer(None)


def main(args: argparse.Namespace) -> int:
    recognizer = recognizer_for(args.backend)
    learned = LearnedRecognizer.from_files(args.learned, args.mirrored) if args.learned else None
    for frame in read_trajectories(args.file):
        for gesture in recognizer.update(frame.t, frame.hands, frame.body, args.mirrored):
            print(json.dumps(gesture.to_json()))
        for gesture in learned.update(frame.t, frame.hands, frame.body) if learned else ():
            print(json.dumps(gesture.to_json()))
    for gesture in recognizer.finish():  # the file ended: swipes being confirmed complete
        print(json.dumps(gesture.to_json()))
    return 0
