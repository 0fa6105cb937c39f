"""How far the body lurches towards or away from the camera around a hand's stroke.

A swipe is made by the arm of a body that stands: the torso may lean sideways into the sweep, but
it does not rock forward or back. Kicking a ball, lunging or stepping does (the spine joint of
most kicks moves 150-290 mm within 0.3 s, real swipes' 40 mm at most), and an arm swings across
the body for balance meanwhile, which relative to the torso looks like a swipe. The torso's path
is read back from a hand's samples (each holds the hand in the world and relative to the torso).
"""
from __future__ import annotations

from typing import Iterable

from backends.engine.strokes import Z, Sample


def torso_depth(s: Sample) -> float:
    """The torso's distance from the camera when `s` was taken, mm."""
    return float(s.world[Z] - s.p[Z])


def lurch(samples: Iterable[Sample], since: float, window_s: float) -> float:
    """The furthest the torso moved towards or away from the camera within `window_s`, mm, over the
    samples from `window_s` before `since` on. Measured between samples at least `window_s` apart, so
    a depth tracker's torso that jumps for a frame and drifts back counts for no more than its jump."""
    path = [(s.t, torso_depth(s)) for s in samples if s.t >= since - 2 * window_s]
    furthest, ref = 0.0, -1
    for t, z in path:
        while ref + 1 < len(path) and t - path[ref + 1][0] >= window_s:
            ref += 1
        if t >= since and ref >= 0:
            furthest = max(furthest, abs(z - path[ref][1]))
    return furthest
