"""The live status line during a show and the summary at exit (rich, on stderr)."""
from __future__ import annotations

import time
from typing import Callable

from rich.console import Console
from rich.live import Live
from rich.table import Table

from host.metrics import Metrics

stderr = Console(stderr=True)


def line(m: Metrics) -> str:
    sfps, rfps = m.live()
    lat = m.latency(recent=120)
    last = ", ".join(g.name for g in m.last_gestures) or "-"
    return (f"[bold]{m.backend}[/] <- {m.input_label}  sFPS {sfps:5.1f}  rFPS {rfps:5.1f}  eff {(sfps + rfps) / 2:5.1f}  "
            f"latency p50 {lat['p50']:5.1f} ms p99 {lat['p99']:5.1f} ms  dropped {m.dropped}  "
            f"gestures {m.gestures} (last: {last})  {m.source_line()}")


class StatusLine:
    """Redraws at most 4 times a second, only on a terminal (logs stay clean)."""

    def __init__(self, extra: Callable[[], str] | None = None) -> None:
        self.enabled = stderr.is_terminal
        self.extra = extra  # a second line, e.g. what `issv serve` has published
        self._live: Live | None = None
        self._next = 0.0

    def __enter__(self) -> "StatusLine":
        if self.enabled:
            self._live = Live("", console=stderr, refresh_per_second=4, transient=True, redirect_stdout=True)
            self._live.__enter__()
        return self

    def __call__(self, show) -> None:
        now = time.monotonic()
        if self._live is not None and now >= self._next:
            self._next = now + 0.25
            text = line(show.metrics)
            self._live.update(text if self.extra is None else f"{text}\n{self.extra()}")

    def __exit__(self, *exc: object) -> None:
        if self._live is not None:
            self._live.__exit__(*exc)


def summary(m: Metrics) -> None:
    d = m.to_json()
    table = Table(title=f"issv show summary: backend {d['backend']}", show_header=False)
    table.add_row("frames (sensor)", str(d["frames"]))
    if m.input_label:
        table.add_row("input", m.input_label)
    if d["source_fps"]:  # a backend without a source (osc-in) has no source rate: its input says its own
        table.add_row("source rate", f"{d['source_fps']:.2f} Hz")
    table.add_row("sFPS / rFPS / effective", f"{d['sfps']:.2f} / {d['rfps']:.2f} / {d['effective_fps']:.2f}")
    lat = d["latency_ms"]
    table.add_row("capture -> effect latency", f"p50 {lat['p50']:.2f} ms  p95 {lat['p95']:.2f} ms  p99 {lat['p99']:.2f} ms")
    table.add_row("dropped frames (newest wins)", str(d["dropped"]))
    if m.source_health is not None and m.source_health():
        table.add_row("source (its own report)", m.source_health())
    if m.failed:  # not in the JSON document: its keys are an interface
        table.add_row("frames the backend failed on (skipped)", str(m.failed))
    by_name = ", ".join(f"{k} {v}" for k, v in d["gestures_by_name"].items()) or "none"
    table.add_row("gestures completed", f"{d['gestures']} ({by_name})")
    stderr.print(table)
