"""`issv compare RECORDING --backends a,b,c -o DIR`: the same recorded depth through each backend,
then DIR/report.md with PNG plots (research question 2 of the thesis, reproducible by a crew)."""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

from host.compare import backend_entry, run_backend
from host.errors import UserError
from host.plugins import default_registry
from host.recording import Recording
from host.status import stderr

HELP = "run several backends on the identical depth of a recording and write a Markdown report with plots"


def backend_list(text: str) -> list[str]:
    names = [n.strip() for n in text.split(",") if n.strip()]
    if not names:
        raise argparse.ArgumentTypeError("expected backend names separated by commas, e.g. openiss,openiss-nite")
    return names


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("recording", help="an MCAP recording made by `issv record`")
    p.add_argument("--backends", required=True, type=backend_list, metavar="A,B,C",
                   help="backends to compare (`replay` = the recording's own tracks, `truth` = its ground truth)")
    p.add_argument("-o", "--output", required=True, metavar="DIR", help="where report.md and its PNGs go")


def describe(path: Path) -> "report.RecordingInfo":
    """Frame count, duration and size of the recording (reads the depth headers, not the pixels)."""
    from host import report  # matplotlib loads only when a report is made
    with Recording(path) as rec:
        first = last = None
        frames = 0
        for header, _ in rec.depth_headers():
            first = first or header
            last, frames = header, frames + 1
        if first is None:
            raise UserError(f"{path}: the recording has no depth images to compare backends on")
        return report.RecordingInfo(path, frames, last.t - first.t, (int(first.doc["width"]), int(first.doc["height"])),
                                    rec.meta, rec.complete)


def main(args: argparse.Namespace) -> int:
    from host import report

    path = Path(args.recording)
    registry = default_registry()
    for name in args.backends:  # refuse unknown names before anything runs
        backend_entry(registry, name)
    info = describe(path)
    runs = []
    with Progress(TextColumn("{task.description:>18}"), BarColumn(), MofNCompleteColumn(),
                  TextColumn("{task.fields[rate]}"), TimeElapsedColumn(), console=stderr) as progress:
        for name in args.backends:
            task = progress.add_task(name, total=info.frames, rate="")

            def update(show, task=task) -> None:
                sfps, _ = show.metrics.live()
                progress.update(task, completed=show.metrics.frames, rate=f"{sfps:6.1f} sFPS")

            run = run_backend(name, path, update, registry)
            progress.update(task, completed=len(run.frame_times),
                            rate="failed" if run.error else f"{run.metrics['sfps']:6.1f} sFPS")
            runs.append(run)
    for run in runs:
        if run.error:
            print(f"issv: backend {run.backend!r} failed: {run.error}", file=sys.stderr)
    out = report.write(Path(args.output), info, runs)
    print(f"issv: report written to {out}", file=sys.stderr)
    return 0 if any(r.error is None for r in runs) else 1
