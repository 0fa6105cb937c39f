"""A wave told by its rhythm: a raised hand swinging side to side, however small the swings.

A hand waved from the wrist or with the fingers may move the skeleton's hand joint only 10-25 mm,
below the hysteresis that keeps a tracker's jitter from cutting strokes (strokes.py), so such a wave
never makes the strokes of an ordinary wave. What tells it from a raised hand that jitters or
fidgets is its rhythm: several swings in a row, each lasting as long as a wave's swing (1.5-5 Hz),
each running sideways clearly more than the hand moves up, down or forward meanwhile, with the hand
at the shoulders or higher. A tracker's jitter reverses within a frame or two and moves the joint
along every axis alike; a hand held up drifts or fidgets without keeping time.
"""
from __future__ import annotations

import numpy as np

from backends.engine.rules import GestureRules
from backends.engine.strokes import X, Y, Z, AxisStrokes, Sample, Stroke


def spread_across(stroke: Stroke) -> float:
    """How far the hand ranged up and down or forward and back during the stroke, mm (the larger)."""
    p = np.array([q.p for q in stroke.samples])
    return float(max(np.ptp(p[:, Y]), np.ptp(p[:, Z])))


class Rhythm:
    """One hand's side-to-side swings, cut with a small hysteresis, and the run of consecutive
    swings that keep a wave's time so far."""

    def __init__(self, rules: GestureRules) -> None:
        self.rules = rules
        # a swing held at its extreme for longer than a wave's swing lasts ends the run
        self.swings = AxisStrokes(X, rules.wave_rhythm_hysteresis_mm, rules.wave_rhythm_max_swing_s)
        self.run: list[Stroke] = []

    def update(self, s: Sample) -> Stroke | None:
        """Add a sample; returns the swing that it showed to be over, if any."""
        return self.swings.update(s)

    def in_time(self, swing: Stroke, size: float) -> bool:
        """Could the swing be one of a wave's: as long as a wave's swing, mostly sideways, the hand
        seen throughout and at the shoulders or higher (distances for the performer's `size`)?"""
        r = self.rules
        return (r.wave_min_swing_s <= swing.duration <= r.wave_rhythm_max_swing_s
                and swing.travel >= r.wave_rhythm_min_dominance * spread_across(swing)
                and swing.lowest >= swing.start.shoulder - r.wave_rhythm_max_below_shoulder_mm * size
                and swing.end.seen_since == swing.start.seen_since)

    def add(self, swing: Stroke, counts: bool) -> list[Stroke]:
        """The run of swings in time, each starting where the last one turned, after `swing`."""
        if not counts or (self.run and self.run[-1].end is not swing.start):
            self.run.clear()
        if counts:
            self.run.append(swing)
        return self.run
