"""`issv track CLIP.npz [...]`: run a backend over depth clips as fast as possible, print its output.

Per frame one `hands` line (Frame.hands_json()) and one line per gesture event (Gesture.to_json()),
the event lines of docs/architecture.md; after a clip's last frame, the gestures its end completed
(Backend.finish()). With several clips every line also carries `"clip": PATH`, so a directory of
clips is measured in one process (one backend per clip: each starts fresh).

Each clip runs through the host's frame loop (host.loop.Show, unpaced, no effects), so a backend
that raises meets the rules it meets on stage: a frame it fails on is skipped, said once, and the
clip goes on; failing frame after frame ends the clip with one line naming the clip and the frame.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from host.app import plugin_class
from host.commands.gestures import add_learned_argument
from host.contracts import PluginUnavailable, Stage
from host.errors import UserError
from host.learned.gesture_file import load
from host.learned_users import LearnedByUser
from host.loop import Limits, PacedSource, Show
from host.tap import SensorTap

HELP = "track hands and gestures in depth clips (.npz) with a backend; prints event lines"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("clips", nargs="+", type=Path, help="depth clips (.npz, docs/architecture.md)")
    p.add_argument("--backend", default="openiss", help="backend to run (default: openiss)")
    add_learned_argument(p)


def track(clip: Path, backend_cls, source_cls, tag: str | None, out, learned: list[Path] = ()) -> None:
    """Play one clip through a fresh backend (and fresh learned gestures), writing its lines to `out`
    (on the sensor thread, in the order the backend made them)."""
    source = source_cls(source_cls.Options(path=str(clip)))
    inner = backend_cls(PacedSource(source, realtime=False), backend_cls.Options())
    backend = LearnedByUser(inner, [load(f) for f in learned]) if learned else inner  # as the show does
    extra = {"clip": tag} if tag is not None else {}

    def line(doc: dict) -> None:
        out.write(json.dumps({**doc, **extra}) + "\n")

    def frame_lines(frame) -> None:
        line(frame.hands_json())
        for gesture in frame.gestures:
            line(gesture.to_json())

    def end_lines(gestures) -> None:  # the clip ended: gestures still being confirmed complete
        for gesture in gestures:
            line(gesture.to_json())

    show = Show(SensorTap(backend, frame_lines, observe_end=end_lines), [], Stage((640, 480), 60.0, backend_cls.name),
                limits=Limits(), label=str(clip))
    try:
        show.run()
    except PluginUnavailable as error:
        raise UserError(f"backend {backend_cls.name!r}: {error}") from None
    error = show.sensor_error
    if isinstance(error, UserError):
        raise error
    if error is not None:  # a bug met on this clip: say where, so it can be replayed
        raise UserError(f"backend {backend_cls.name!r} raised {type(error).__name__} on frame {show.failed_frame} of "
                        f"{clip}: {error} (a bug: please report it with that clip)") from error


def main(args: argparse.Namespace) -> int:
    backend_cls = plugin_class("backends", args.backend)
    if not backend_cls.needs_source:
        raise UserError(f"backend {backend_cls.name!r} does not track depth (it makes its own frames)")
    source_cls = plugin_class("sources", "clip")
    several = len(args.clips) > 1
    for clip in args.clips:
        track(clip, backend_cls, source_cls, str(clip) if several else None, sys.stdout, args.learned)
    return 0
