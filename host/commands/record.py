"""`issv record PROFILE -o FILE.mcap`: track a profile's source with its backend and record it all."""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from host import profile as profiles
from host.assemble import make_backend, make_stage
from host.commands.run import check_sensor, play
from host.loop import Limits, Show
from host.metrics import Metrics
from host.model import Frame
from host.plugins import default_manager
from host.recording import RecordingWriter
from host.status import StatusLine
from host.tap import SensorTap

HELP = "record a profile's depth, hands, gestures and metrics to an MCAP file (no effects, no window)"
METRICS_EVERY_S = 1.0


class RecordingSink:
    """Writes every tracked frame, the show's metrics about once a second, and the final ones."""

    def __init__(self, writer: RecordingWriter) -> None:
        self.writer = writer
        self.metrics: Metrics | None = None  # the show's, set once the show exists
        self._next_metrics = 0.0

    def frame(self, frame: Frame) -> None:
        self.writer.write_frame(frame)
        if self.metrics is not None and time.monotonic() >= self._next_metrics:
            self._next_metrics = time.monotonic() + METRICS_EVERY_S
            self.writer.write_metrics(self.metrics.to_json())

    def finish(self) -> None:
        if self.metrics is not None:
            self.writer.write_metrics(self.metrics.to_json(), final=True)
        self.writer.close()


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("profile", help="a profile TOML file: its source and backend are recorded")
    p.add_argument("-o", "--output", required=True, metavar="FILE.mcap", help="the recording to write")
    p.add_argument("--seconds", type=float, metavar="S", help="stop after S seconds of source time")
    p.add_argument("--frames", type=int, metavar="N", help="stop after N sensor frames")
    p.add_argument("--fast", action="store_true", help="do not pace recorded sources: as fast as possible")


def main(args: argparse.Namespace) -> int:
    prof = profiles.load(args.profile)
    backend = make_backend(prof, realtime=not args.fast)
    source = prof.source.ref.name if prof.source is not None else ""
    writer = RecordingWriter(args.output, {"profile": str(prof.path), "backend": backend.name, "source": source})
    sink = RecordingSink(writer)
    tap = SensorTap(backend, sink.frame, closed=sink.finish, observe_end=writer.write_end_gestures)
    stage = make_stage(prof, backend)
    status = StatusLine()
    show = Show(tap, [], stage, pm=default_manager(), limits=Limits(args.frames, args.seconds), status=status)
    sink.metrics = show.metrics
    try:
        play(show, status)
    finally:
        writer.close()
        if writer.frames == 0:
            Path(args.output).unlink(missing_ok=True)
    check_sensor(show)
    print(f"issv: recorded {writer.frames} frames to {args.output}", file=sys.stderr)
    return 0
