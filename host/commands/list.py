"""`issv list`: every installed backend, source and effect, and whether it can run here."""
from __future__ import annotations

import argparse
import json

from rich.console import Console
from rich.table import Table

from host.plugins import KINDS, default_registry

HELP = "list backends, sources and effects with their availability"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", action="store_true", help="machine-readable output")


def main(args: argparse.Namespace) -> int:
    registry = default_registry()
    data = {kind: [r.to_json() for r in registry.all(kind)] for kind in KINDS}
    if args.json:
        print(json.dumps(data, indent=2))
        return 0
    console = Console()
    for kind, items in data.items():
        table = Table(title=kind, title_justify="left")
        framed = kind in ("backends", "sources")
        for column in ("name", "available", "plugin", *(["frames"] if framed else []), "how to fix"):
            table.add_column(column)
        for item in items:
            frames = [item.get("frames") or "own"] if framed else []  # own: the backend makes its frames
            table.add_row(item["name"], "yes" if item["available"] else "[red]no[/]", item["plugin"], *frames,
                          item["reason"] or "")
        console.print(table)
    return 0
