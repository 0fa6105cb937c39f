"""Host overhead per frame with 1 and 10 effects, and sFPS / source rate over a paced 10 s run.

Targets (issue 3): <= 0.5 ms per frame with 10 effects; sFPS / source rate = 1.00.
"""
from __future__ import annotations

import time

import numpy as np

from bench.common import parse_args, percentiles, report
from host import (Backend, DepthFrame, Effect, Frame, Gesture, GestureState, GestureType, Hand, HandState,
                  Intrinsics, Side, Stage)
from host.loop import EffectSlot, Limits, PacedSource, Show
from sources.clip import ClipSource


class NoOp(Effect):
    """An effect that does nothing, so only the host's own cost is measured."""

    name = "noop"

    def on_gesture(self, gesture):
        pass

    def on_frame(self, frame):
        pass


def _frame(i: int, depth: DepthFrame) -> Frame:
    hands = (Hand(1, HandState.TRACKING, (100.0, 0.0, 2000.0), Side.LEFT),
             Hand(2, HandState.TRACKING, (-100.0, 0.0, 2000.0), Side.RIGHT))
    gestures = (Gesture(GestureType.WAVE, GestureState.COMPLETE, (0.0, 0.0, 2000.0), 1, Side.LEFT, 1.0, i / 30),)
    return Frame(i, time.time(), depth, hands, gestures, "bench")


def host_overhead(n_effects: int, frames: int = 3000) -> list[float]:
    """Microseconds per frame spent by the host: the sensor-side hand-off plus one show tick."""
    depth = DepthFrame(np.zeros((480, 640), np.uint16), Intrinsics.from_fov(640, 480, 57, 43))
    backend = Backend(None)
    backend.name = "bench"
    slots = [EffectSlot(NoOp(), f"effects[{i}]") for i in range(n_effects)]
    show = Show(backend, slots, Stage((640, 480), 60.0, "bench"))
    for slot in slots:
        slot.effect.setup(show.stage)
    per_frame, count = [], 0
    for i in range(frames):
        frame = _frame(i, depth)
        t0 = time.perf_counter()
        show.metrics.sensor_frame(frame)          # what the sensor thread does per frame
        show.gestures.put_all(frame.gestures)
        show.latest.publish(frame)
        count = show._deliver(count)              # what the show loop does per frame
        show._render()
        per_frame.append((time.perf_counter() - t0) * 1e6)
    return per_frame[100:]


def paced_rate(seconds: float, clip_path: str | None) -> dict:
    """Run the truth backend on a clip (looped) paced in real time; compare sFPS to the source rate."""
    from backends.truth import TruthBackend

    source = ClipSource(ClipSource.Options(path=clip_path, loop=True))
    backend = TruthBackend(PacedSource(source, realtime=True))
    show = Show(backend, [EffectSlot(NoOp(), "effects[0]")], Stage((640, 480), 60.0, "truth"),
                limits=Limits(seconds=seconds))
    m = show.run()
    return {"source_fps": m.source_fps, "sfps": m.sfps, "ratio": m.sfps / m.source_fps, "rfps": m.rfps}


def main() -> None:
    def extra(p):
        p.add_argument("--seconds", type=float, default=10.0, help="length of the paced run")
        p.add_argument("--clip", default=None, help="clip for the paced run (default: a generated one)")
    args = parse_args(__doc__, extra)
    figures: dict = {}
    rows = []
    for n in (1, 10):
        p = percentiles(host_overhead(n))
        figures[f"overhead_us_{n}_effects"] = p
        rows.append([f"host overhead, {n} effect(s) (us/frame)", p["p50"], p["p90"], p["p99"], "<= 500 us (10 effects)"])
    clip = args.clip
    if clip is None:
        import tempfile
        from pathlib import Path
        clip = str(Path(tempfile.mkdtemp()) / "bench.npz")
        depth = np.full((30, 240, 320), 2500, np.uint16)
        np.savez(clip, depth=depth, timestamps=np.arange(30) / 30.0, intrinsics=np.array([285.63, 285.63, 160, 120]))
    rate = paced_rate(args.seconds, clip)
    figures["paced"] = rate
    rows.append([f"sFPS / source rate ({args.seconds:.0f} s paced)", rate["ratio"], "", "", "1.00"])
    report("issv host bench", figures, rows, ["figure", "p50 / value", "p90", "p99", "target"], args.json)


if __name__ == "__main__":
    main()
