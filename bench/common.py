"""What every bench shares: argument parsing, percentiles and the table/JSON printout."""
from __future__ import annotations

import argparse
import json

import numpy as np
from rich.console import Console
from rich.table import Table


def parse_args(description: str, extra=None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--json", action="store_true", help="print one JSON object of the figures")
    if extra is not None:
        extra(parser)
    return parser.parse_args()


def percentiles(values, ps=(50, 90, 99)) -> dict[str, float]:
    data = np.asarray(values, dtype=float)
    if data.size == 0:
        return {f"p{p}": float("nan") for p in ps}
    return {f"p{p}": float(v) for p, v in zip(ps, np.percentile(data, ps))}


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
