"""Render time of the synthetic performer per frame (pose, rasterisation, Kinect noise and holes).

A frame must cost a few milliseconds so the sensor thread keeps 30 Hz with room for a backend.
Median and p90 of `read()` over 100 frames of the default show, per resolution and setting, in
wall-clock time and in this thread's CPU time (the fairer figure on a machine shared with others);
the duet and trio scenes (several performers, their truth label image too) from their crossing on.
"""
from __future__ import annotations

import time

from bench.common import parse_args, percentiles, report
from sources.synthetic import SyntheticOptions, SyntheticSource

SETTINGS = {
    "kinect (room, noise, holes)": {},
    "clean (room, no noise or holes)": {"noise": 0, "holes": 0},
    "background none": {"background": "none"},
    "duet scene (2 performers)": {"scene": "duet"},
    "trio scene (3 performers)": {"scene": "trio"},
    "quartet scene (4 performers)": {"scene": "quartet"},
}


def read_times(frames: int = 100, **options) -> tuple[list[float], list[float]]:
    """Wall and CPU milliseconds per read(), after the first second (the performer idles there;
    a scene's performers then start walking and cross)."""
    source = SyntheticSource(SyntheticOptions(seed=1, loop=True, **options))
    source.open()
    for _ in range(30 if "scene" not in options else 90):
        source.read()
    wall, cpu = [], []
    for _ in range(frames):
        start, start_cpu = time.perf_counter(), time.thread_time()
        source.read()
        wall.append((time.perf_counter() - start) * 1e3)
        cpu.append((time.thread_time() - start_cpu) * 1e3)
    return wall, cpu


def main() -> None:
    args = parse_args(__doc__.splitlines()[0])
    rows, figures = [], {}
    for width, height in ((640, 480), (320, 240)):
        for label, options in SETTINGS.items():
            wall, cpu = read_times(width=width, height=height, **options)
            w, c = percentiles(wall, (50, 90)), percentiles(cpu, (50,))
            rows.append([f"{width}x{height}", label, w["p50"], w["p90"], c["p50"]])
            figures[f"{width}x{height} {label}"] = {"median_ms": w["p50"], "p90_ms": w["p90"], "cpu_median_ms": c["p50"]}
    report("synthetic source: ms per frame", figures, rows,
           ["size", "setting", "median ms", "p90 ms", "CPU median ms"], args.json)


if __name__ == "__main__":
    main()
