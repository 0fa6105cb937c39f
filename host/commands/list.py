"""`issv list`: every installed backend, source and effect, whether it can run here, and the
cameras connected now (for sources that open devices: model, serial, firmware, modes, problems)."""
from __future__ import annotations

import argparse
import dataclasses
import json

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from host.contracts import DeviceInfo
from host.plugins import KINDS, Registered, default_registry

HELP = "list backends, sources and effects with their availability"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", action="store_true", help="machine-readable output")


def devices(entry: Registered) -> list[dict] | None:
    """The source's connected devices as JSON, None for sources that read files."""
    if entry.availability() is not None:
        return None
    try:
        found = entry.cls.devices()
    except Exception as error:  # a broken device query is itself a problem to show
        found = [DeviceInfo("?", problem=f"device query raised {type(error).__name__}: {error}")]
    return None if found is None else [dataclasses.asdict(d) for d in found]


def device_lines(items: list[dict]) -> list[str]:
    """Each camera source's connected devices, a few lines each (long udev rules stay whole)."""
    out = []
    for item in items:
        found = item.get("devices")
        if found == []:
            out.append(f"[bold]{item['name']}[/]: no device connected (plug one in)")
        for d in found or []:
            out.append(f"[bold]{item['name']}[/]: {escape(d['model'])}  serial {escape(d['serial'] or '?')}  "
                       f"firmware {escape(d['firmware'] or '?')}")
            out += [f"    mode {escape(mode)}" for mode in d["modes"]]
            out += [f"    [red]cannot open it[/]: {escape(d['problem'])}"] if d["problem"] else []
    return out


def table(kind: str, items: list[dict]) -> Table:
    """One kind's plugins; the texts are escaped: `pip install 'issv[webcam]'` is no rich markup."""
    out = Table(title=kind, title_justify="left")
    framed = kind in ("backends", "sources")
    for column in ("name", "available", "plugin", *(["frames"] if framed else []), "how to fix"):
        out.add_column(column)
    for item in items:
        frames = [item.get("frames") or "own"] if framed else []  # own: the backend makes its frames
        out.add_row(escape(item["name"]), "yes" if item["available"] else "[red]no[/]", escape(item["plugin"]),
                    *frames, escape(item["reason"] or ""))
    return out


def main(args: argparse.Namespace) -> int:
    registry = default_registry()
    data = {kind: [r.to_json() for r in registry.all(kind)] for kind in KINDS}
    for item, entry in zip(data["sources"], registry.all("sources")):
        found = devices(entry)
        if found is not None:
            item["devices"] = found
    if args.json:
        print(json.dumps(data, indent=2))
        return 0
    console = Console()
    for kind, items in data.items():
        console.print(table(kind, items))
    console.print("[italic]devices[/]")
    for text in device_lines(data["sources"]):
        console.print(text, soft_wrap=True)
    return 0
