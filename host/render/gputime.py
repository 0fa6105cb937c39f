"""Each layer's GPU time for the HUD, from GL timer queries, where the driver reports it.

The queries are read after the frame was presented (the renderer waits for it), so reading
them never stalls the pipeline. A driver without timer queries (or llvmpipe
on a context that has not flushed yet) answers 2^32-1 ns: such answers are skipped, and while no
layer has a real time the HUD says "not reported" rather than showing a number.
"""
from __future__ import annotations

import moderngl

UNREPORTED_NS = 2**32 - 1


class LayerTimes:
    def __init__(self, ctx: moderngl.Context) -> None:
        self.ctx = ctx
        self.queries: dict[str, moderngl.Query] = {}
        self.ms: dict[str, float] = {}  # smoothed, per layer name

    def query(self, name: str) -> moderngl.Query:
        if name not in self.queries:
            self.queries[name] = self.ctx.query(time=True)
        return self.queries[name]

    def collect(self) -> None:
        """After the frame is finished: the elapsed times, smoothed over about ten frames."""
        for name, query in self.queries.items():
            elapsed = query.elapsed
            if elapsed <= 0 or elapsed >= UNREPORTED_NS:
                continue
            ms = elapsed / 1e6
            self.ms[name] = ms if name not in self.ms else 0.9 * self.ms[name] + 0.1 * ms

    @property
    def reported(self) -> bool:
        return bool(self.ms)

    def line(self) -> str:
        if not self.reported:
            return "layer GPU ms: not reported by this driver"
        return "GPU ms " + "  ".join(f"{name} {ms:.1f}" for name, ms in self.ms.items())

    def release(self) -> None:
        self.queries.clear()  # moderngl's Query has no release(): its GL objects go with the context
