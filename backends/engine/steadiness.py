"""How fast the body lurches towards or away from the camera around a hand's stroke.

A swipe is made by the arm of a body that stands: the torso may lean sideways into the sweep, but
it does not rock forward or back. Kicking a ball, lunging or stepping does (the spine joint moves
0.5-0.9 m/s towards or away from the camera), and the arms swing across the body for balance
meanwhile, which relative to the torso looks like a swipe. The torso's path is read back from a
hand's samples (each holds the hand in the world and relative to the torso).
"""
from __future__ import annotations

from typing import Iterable

from backends.engine.strokes import Z, Sample


def torso_depth(s: Sample) -> float:
    """The torso's distance from the camera when `s` was taken, mm."""
    return float(s.world[Z] - s.p[Z])


def lurch_speed(samples: Iterable[Sample], since: float, window_s: float) -> float:
    """The fastest the torso moved towards or away from the camera, mm/s, each speed measured over
    `window_s` (a skeleton's torso jitters by several mm per frame), at the samples from `since` on."""
    path = [(s.t, torso_depth(s)) for s in samples if s.t >= since - window_s]
    fastest, first = 0.0, 0
    for t, z in path:
        while t - path[first][0] > window_s:
            first += 1
        t0, z0 = path[first]
        if t >= since and t > t0:
            fastest = max(fastest, abs(z - z0) / (t - t0))
    return fastest
