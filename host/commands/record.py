"""`issv record PROFILE -o FILE.mcap`: track a profile's source with its backend and record it all."""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from host.app import SensorShow, add_limit_arguments
from host.model import Frame
from host.recording import RecordingWriter

HELP = "record a profile's depth, hands, gestures and metrics to an MCAP file (no effects, no window)"
METRICS_EVERY_S = 1.0


class RecordingSink:
    """Writes every tracked frame, the show's metrics about once a second, and the final ones."""

    def __init__(self, writer: RecordingWriter, show: SensorShow) -> None:
        self.writer = writer
        self.show = show  # its metrics exist once it runs
        self._next_metrics = 0.0

    def frame(self, frame: Frame) -> None:
        self.writer.write_frame(frame)
        if self.show.metrics is not None and time.monotonic() >= self._next_metrics:
            self._next_metrics = time.monotonic() + METRICS_EVERY_S
            self.writer.write_metrics(self.show.metrics.to_json())

    def finish(self) -> None:
        if self.show.metrics is not None:
            self.writer.write_metrics(self.show.metrics.to_json(), final=True)
        self.writer.close()


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("profile", help="a profile TOML file: its source and backend are recorded")
    p.add_argument("-o", "--output", required=True, metavar="FILE.mcap", help="the recording to write")
    add_limit_arguments(p)
    p.add_argument("--fast", action="store_true", help="do not pace recorded sources: as fast as possible")


def main(args: argparse.Namespace) -> int:
    show = SensorShow(args.profile, fast=args.fast)
    writer = RecordingWriter(args.output, {"profile": str(show.profile.path), "backend": show.backend.name,
                                           "source": show.source_name})
    sink = RecordingSink(writer, show)
    try:
        show.run(sink.frame, observe_end=writer.write_end_gestures, closed=sink.finish,
                 frames=args.frames, seconds=args.seconds)
    finally:
        writer.close()
        if writer.frames == 0:
            Path(args.output).unlink(missing_ok=True)
    print(f"issv: recorded {writer.frames} frames to {args.output}", file=sys.stderr)
    return 0
