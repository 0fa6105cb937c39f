"""What every bench shares: argument parsing, the real data folder, percentiles and the table/JSON printout."""
from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
from collections.abc import Iterable
from pathlib import Path
from typing import TypeVar

import numpy as np
from rich.console import Console
from rich.progress import track
from rich.table import Table

from host.status import stderr


DATA_ENV = "ISSV_DATA"
BESIDE_REPO = Path(__file__).resolve().parents[2] / "shared" / "data"  # a workspace's shared folder


def default_data() -> Path | None:
    """$ISSV_DATA, else ../shared/data beside the repo if it exists, else None."""
    if os.environ.get(DATA_ENV, "").strip():
        return Path(os.environ[DATA_ENV])
    return BESIDE_REPO if BESIDE_REPO.is_dir() else None


def add_data_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--data", type=Path, default=default_data(), metavar="DIR",
                        help=f"the folder of real data sets (default: ${DATA_ENV}, then ../shared/data if present)")


def data_set(args: argparse.Namespace, name: str, skipped: str) -> Path | None:
    """The real data set `name` in --data, or None after one line saying what is skipped without it."""
    root: Path | None = args.data
    if root is not None and (root / name).is_dir():
        return root / name
    where = f"{root / name} does not exist" if root is not None else f"no --data DIR and no ${DATA_ENV}"
    print(f"bench: {where}: skipping {skipped}", file=sys.stderr)
    return None


def parse_args(description: str, extra=None, data: bool = False) -> argparse.Namespace:
    """--json, --data DIR when the bench reads real data sets (`data`), and the bench's own options."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--json", action="store_true", help="print one JSON object of the figures")
    if data:
        add_data_argument(parser)
    if extra is not None:
        extra(parser)
    return parser.parse_args()


def percentiles(values, ps=(50, 90, 99)) -> dict[str, float]:
    data = np.asarray(values, dtype=float)
    if data.size == 0:
        return {f"p{p}": float("nan") for p in ps}
    return {f"p{p}": float(v) for p, v in zip(ps, np.percentile(data, ps))}


T = TypeVar("T")


def tracked(items: Iterable[T], what: str, total: int | None = None) -> Iterable[T]:
    """`items` as they come, with a progress bar saying `what` on stderr while minutes of work run
    (the table or JSON stays alone on stdout)."""
    return track(items, what, total=total, console=stderr, transient=True)


def report(title: str, figures: dict, rows: list[list], columns: list[str], as_json: bool) -> None:
    """Print `rows` as a table, or `figures` as one JSON object."""
    if as_json:
        print(json.dumps(figures))
        return
    table = Table(title=title)
    for column in columns:
        table.add_column(column)
    for row in rows:
        table.add_row(*[f"{v:.3f}" if isinstance(v, float) else str(v) for v in row])
    console = Console()
    if not console.is_terminal:  # a log or a pipe: keep every column whole
        console = Console(width=200)
    console.print(table)


def stop(proc: subprocess.Popen) -> None:
    """Stop a helper started in its own process group: Ctrl-C first, then kill after 10 s."""
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGINT)
    try:
        proc.wait(timeout=10)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
