"""The silhouette per user: milliseconds per sensor frame to upload the frame's image and draw
it over a 1280x720 stage, headless on EGL (llvmpipe without a GPU), for each input the effect
takes: the backend's user labels (two users, each in their colour, looked up in the shader), the
user mask (labels > 0 made on the CPU, one colour) and the depth band (no mask at all).

Every frame is a new sensor frame (a new `seq`), so each one pays its upload, as a 30 Hz source
does; `glFinish` waits for the pixels. "CPU ms" is the process's CPU time per frame (llvmpipe's
threads included): on a shared machine the wall time depends on the others' load, this much less.

Issue 17 asks for one upload per frame and the colour looked up in the shader (no CPU pass over
the pixels): the labels row says what colouring by user costs over the mask's one colour (which
pays `labels > 0` on the CPU instead).
"""
from __future__ import annotations

import time

import numpy as np

from bench.common import parse_args, percentiles, report
from effects.silhouette import Silhouette
from host import DepthFrame, Frame, Intrinsics, Stage
from host.app import EffectCanvas, headless_context

STAGE = (1280, 720)
DEPTH = (640, 480)
FRAMES = 200


def scene() -> tuple[np.ndarray, np.ndarray]:
    """Depth (a wall at 4 m, two people at 2 m) and their labels (1 and 2)."""
    w, h = DEPTH
    depth = np.full((h, w), 4000, np.uint16)
    labels = np.zeros((h, w), np.uint8)
    for user, (u0, u1) in ((1, (140, 260)), (2, (380, 500))):
        depth[60:470, u0:u1] = 2000
        labels[60:470, u0:u1] = user
    return depth, labels


def run(kind: str, ctx, fbo) -> dict:
    depth_mm, labels = scene()
    k = Intrinsics.from_fov(*DEPTH, 57.0, 43.0)
    stage = Stage(STAGE, 30.0, "bench", ctx=ctx)
    effect = Silhouette(Silhouette.Options(near_mm=1000, far_mm=3000))
    effect.setup(stage)
    canvas = EffectCanvas(ctx, STAGE)
    times, cpu = [], []
    for i in range(FRAMES):
        depth = DepthFrame(depth_mm, k, i, i / 30)
        frame = Frame(i + 1, depth.capture_time, depth, backend="bench",
                      make_user_labels=(lambda: labels) if kind == "labels" else None,
                      make_user_mask=(lambda: labels > 0) if kind == "mask" else None)
        fbo.clear()
        start, start_cpu = time.perf_counter(), time.process_time()
        canvas.render(effect, frame, fbo)
        ctx.finish()
        times.append((time.perf_counter() - start) * 1000)
        cpu.append((time.process_time() - start_cpu) * 1000)
    effect.close()
    canvas.release()
    return {"input": kind, "ms": {k: round(v, 2) for k, v in percentiles(times[10:]).items()},
            "cpu_ms": round(float(np.mean(cpu[10:])), 2)}


def main() -> None:
    args = parse_args(__doc__.splitlines()[0])
    ctx = headless_context()
    fbo = ctx.simple_framebuffer(STAGE)
    rows = [run(kind, ctx, fbo) for kind in ("labels", "mask", "depth")]
    figures = {"stage": f"{STAGE[0]}x{STAGE[1]}", "depth": f"{DEPTH[0]}x{DEPTH[1]}", "frames": FRAMES, "inputs": rows}
    report(f"silhouette, {FRAMES} sensor frames, {DEPTH[0]}x{DEPTH[1]} onto {STAGE[0]}x{STAGE[1]}", figures,
           [[r["input"], r["ms"]["p50"], r["ms"]["p90"], r["ms"]["p99"], r["cpu_ms"]] for r in rows],
           ["input", "ms p50", "ms p90", "ms p99", "CPU ms (mean)"], args.json)


if __name__ == "__main__":
    main()
