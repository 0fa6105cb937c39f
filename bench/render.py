"""Rendering while tracking runs: rFPS, sFPS, effective FPS and frame-time percentiles of the
stage profile (profiles/stage.toml: synthetic performer, openiss, five render effects, HUD) at
1280x720 and 1920x1080, headless on EGL (llvmpipe without a GPU).

Each size runs twice: capped at the profile's output rate (60 Hz, what a show does) and with the
cap lifted to 240 Hz (what the renderer can do). Frame time is the renderer's own time per frame.
One more row (issue 22): the same profile at 1280x720 with a three-pass feedback ISF filter over
the whole show (Vidvox's Motion Heat Map: a difference pass, a persistent last-frame buffer, the
output) at `scale = 0.5` (its passes run at 640x360 on the full-size show below, then one stretch
onto the stage), uncapped.
"render CPU ms" is the CPU time of the render thread and llvmpipe's threads per frame: on a shared
machine the frame rate depends on the others' load, this much less (`uptime` says how loaded).
Targets (issue 5): >= 60 rFPS at 1280x720; effective FPS >= 45 with a 30 Hz source.
Target (issue 22): >= 30 rFPS with the feedback filter at 1280x720.
"""
from __future__ import annotations

import os
import threading
from pathlib import Path

from bench.common import parse_args, percentiles, report
from host import profile as profiles
from host.assemble import make_backend, make_effects
from host.contracts import Stage
from host.loop import EffectSlot, Limits, Show
from host.render import make_renderer

PROFILE = Path(__file__).resolve().parents[1] / "profiles" / "stage.toml"
SIZES = ((1280, 720), (1920, 1080))


FEEDBACK = "vidvox/Motion Heat Map"
FEEDBACK_SCALE = 0.5


def run(size: tuple[int, int], fps: float, seconds: float, feedback: bool = False) -> dict:
    prof = profiles.load(PROFILE)
    out = prof.model.output
    out.size, out.mode, out.fps = size, "headless", fps
    backend = make_backend(prof, realtime=True)
    slots = [s for s in make_effects(prof) if s.effect.renders]  # no console: stdout stays clean
    if feedback:
        from effects.isf import Isf
        slots.append(EffectSlot(Isf(Isf.Options(shader=FEEDBACK, scale=FEEDBACK_SCALE)), f"effects[{len(slots)}]"))
    stage = Stage(size=size, fps=fps, backend=backend.name)
    renderer = make_renderer(out, stage)
    show = Show(backend, slots, stage, renderer=renderer, limits=Limits(seconds=seconds))
    before = render_cpu_s()
    m = show.run()
    after = render_cpu_s()
    cpu = sum(v - before.get(t, 0.0) for t, v in after.items()) if before is not None and after else None
    if show.sensor_error is not None:
        raise SystemExit(f"bench.render: backend failed: {show.sensor_error}")
    frame = percentiles(list(renderer.frame_ms)[30:])  # without the first frames (shader compiles)
    return {"size": f"{size[0]}x{size[1]}", "cap_hz": fps, "feedback": f"{FEEDBACK} at scale {FEEDBACK_SCALE}" if feedback else None, "rfps": round(m.rfps, 2), "sfps": round(m.sfps, 2),
            "effective_fps": round(m.effective_fps, 2), "source_fps": m.source_fps,
            "render_cpu_ms": round(cpu * 1000 / len(renderer.frame_ms), 1) if cpu and renderer.frame_ms else None,
            "frame_ms": {k: round(v, 2) for k, v in frame.items()},
            "latency_ms": {k: round(v, 2) for k, v in m.latency().items()}, "gestures": m.gestures}


def main() -> None:
    args = parse_args(__doc__.splitlines()[0], lambda p: p.add_argument(
        "--seconds", type=float, default=8.0, help="seconds of source time per run (default 8)"))
    runs = [run(size, cap, args.seconds) for size in SIZES for cap in (60.0, 240.0)]
    runs.append(run(SIZES[0], 240.0, args.seconds, feedback=True))
    rows = [[r["size"] + (" + 3-pass ISF" if r["feedback"] else ""), f"{r['cap_hz']:.0f}", r["rfps"], r["sfps"], r["effective_fps"], r["frame_ms"]["p50"],
             r["frame_ms"]["p90"], r["frame_ms"]["p99"], r["render_cpu_ms"], r["latency_ms"]["p50"]] for r in runs]
    hd = next(r for r in runs if r["size"] == "1280x720" and r["cap_hz"] == 240.0 and not r["feedback"])
    isf = runs[-1]
    figures = {"profile": str(PROFILE.name), "renderer": renderer_name(), "cores": os.cpu_count(),
               "load_average": os.getloadavg(), "runs": runs,
               "targets": {"rfps_1280x720_min": 60, "effective_fps_min": 45, "rfps_1280x720_isf_feedback_min": 30},
               "meets": {"rfps_1280x720": hd["rfps"] >= 60, "effective_fps": hd["effective_fps"] >= 45,
                         "rfps_1280x720_isf_feedback": isf["rfps"] >= 30}}
    report(f"render bench: {PROFILE.name} while tracking runs ({figures['renderer']}, {os.cpu_count()} cores)",
           figures, rows, ["size", "cap Hz", "rFPS", "sFPS", "effective", "frame p50 ms", "p90", "p99",
                           "render CPU ms", "latency p50 ms"], args.json)
    if not args.json:
        print("load average (1, 5, 15 min): " + ", ".join(f"{v:.2f}" for v in figures["load_average"]))


def render_cpu_s() -> dict[str, float] | None:
    """CPU seconds so far of this (render) thread and of llvmpipe's rasteriser threads, by thread id
    (Linux /proc), not the sensor thread's; None where /proc has no per-thread figures."""
    main, tick, out = str(threading.get_native_id()), os.sysconf("SC_CLK_TCK"), {}
    try:
        for tid in os.listdir("/proc/self/task"):
            with open(f"/proc/self/task/{tid}/stat") as f:
                stat = f.read()
            name, fields = stat[stat.index("(") + 1:stat.rindex(")")], stat[stat.rindex(")") + 2:].split()
            if tid == main or name.startswith("llvmpipe"):
                out[tid] = (int(fields[11]) + int(fields[12])) / tick  # utime, stime
    except OSError:
        return None
    return out


def renderer_name() -> str:
    from host.render.context import headless_context
    ctx = headless_context()
    try:
        return ctx.info["GL_RENDERER"]
    finally:
        ctx.release()


if __name__ == "__main__":
    main()
