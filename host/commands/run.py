"""`issv run PROFILE`: play a show."""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from host import profile as profiles
from host.assemble import make_backend, make_effects, make_stage
from host.app import add_limit_arguments, check_sensor, play
from host.loop import Limits, Show
from host.plugins import default_manager
from host.reload import Reloader
from host.status import StatusLine

HELP = "run a show from a profile (windowed, fullscreen, or --headless)"


def size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(v) for v in text.lower().split("x"))
        if w > 0 and h > 0:
            return (w, h)
    except ValueError:
        pass
    raise argparse.ArgumentTypeError(f"expected WIDTHxHEIGHT such as 1280x720, got {text!r}")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("profile", help="a profile TOML file, e.g. profiles/demo.toml")
    p.add_argument("--headless", action="store_true", help="no window (EGL offscreen rendering)")
    add_limit_arguments(p)
    p.add_argument("--metrics-json", metavar="FILE", help="write the final metrics as JSON")
    p.add_argument("--size", type=size, metavar="WxH", help="output size in pixels, e.g. 1920x1080")
    p.add_argument("--out", metavar="FILE.mp4", help="also write the show to a video file")
    p.add_argument("--snapshot", metavar="FILE.png", help="save the last rendered frame as PNG")
    p.add_argument("--fast", action="store_true", help="do not pace recorded sources: as fast as possible, every frame to the effects")
    p.add_argument("--no-reload", action="store_true",
                   help="do not watch the profile and effect sources for edits (live reload is on by default)")


def needs_renderer(prof: profiles.Profile, args: argparse.Namespace) -> bool:
    out = prof.model.output
    wants_window = not args.headless and out.mode != "headless"
    return (any(r.cls.renders for r in prof.effects) or wants_window
            or bool(args.out or args.snapshot or out.video or out.snapshot))


def main(args: argparse.Namespace) -> int:
    prof = profiles.load(args.profile)
    for warning in prof.warnings:
        print(f"issv: {warning}", file=sys.stderr)
    output = prof.model.output
    if args.size:
        output.size = args.size
    if args.headless:
        output.mode = "headless"
    if args.out:
        output.video = args.out
    if args.snapshot:
        output.snapshot = args.snapshot
    backend = make_backend(prof, realtime=not args.fast)
    effects = make_effects(prof)
    stage = make_stage(prof, backend)
    renderer = None
    if needs_renderer(prof, args):
        from host.render import make_renderer  # moderngl is imported only when a show draws
        renderer = make_renderer(output, stage)
    status = StatusLine()
    reloader = None if args.no_reload else Reloader(prof)

    def between_ticks(show: Show) -> None:
        if reloader is not None:
            reloader(show)
        status(show)

    show = Show(backend, effects, stage, pm=default_manager(), limits=Limits(args.frames, args.seconds),
                renderer=renderer, status=between_ticks, lossless=args.fast)
    metrics = play(show, status)
    if args.metrics_json:
        Path(args.metrics_json).write_text(json.dumps(metrics.to_json(), indent=2) + "\n")
    check_sensor(show)
    return 0
