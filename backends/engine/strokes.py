"""Cutting a hand's body-relative path into strokes: runs of motion one way along one axis.

Every gesture of the dictionary is made of strokes: a swipe is one fast dominant stroke, a
wave is alternating horizontal strokes, a click is a forward stroke. A stroke ends when the
hand reverses by more than a hysteresis (so jitter does not cut it) or stops advancing.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

X, Y, Z = 0, 1, 2


@dataclass(frozen=True)
class Sample:
    """One frame of one hand, relative to the body: `p` = hand - torso (mm), `v` its velocity (mm/s);
    `shoulder` is the height of the shoulder line above the torso, `face` the head centre relative
    to the torso; `body_vy` is the torso's vertical speed (mm/s)."""

    t: float
    p: np.ndarray
    v: np.ndarray
    shoulder: float
    face: np.ndarray
    world: tuple[float, float, float]
    body_vy: float = 0.0
    seen_since: float = 0.0  # since when the hand has been seen without a gap

    @property
    def head(self) -> float:
        """Height of the head centre above the torso, mm."""
        return float(self.face[1])


@dataclass(frozen=True)
class Stroke:
    """Motion along `axis` in `direction` (+1 / -1) from `start` to `end` (the extreme reached)."""

    axis: int
    direction: int
    samples: tuple[Sample, ...]

    @property
    def start(self) -> Sample:
        return self.samples[0]

    @property
    def end(self) -> Sample:
        return self.samples[-1]

    @property
    def travel(self) -> float:
        """Net travel along the stroke's direction, mm (>= 0)."""
        return float(self.direction * (self.end.p[self.axis] - self.start.p[self.axis]))

    @property
    def rise(self) -> float:
        """Net travel upward, mm (negative when the stroke went down), whatever its axis."""
        return float(self.end.p[Y] - self.start.p[Y])

    @property
    def duration(self) -> float:
        """Seconds, to the microsecond: three frames at 30 Hz last 0.1 s, where the difference of their
        timestamps is 0.09999999999999998, which rules stated in frames (0.1 s: three at 30 Hz) rejected."""
        return round(self.end.t - self.start.t, 6)

    @property
    def off_axis(self) -> float:
        """Largest net travel along the two other axes, mm."""
        d = np.abs(self.end.p - self.start.p)
        return float(max(d[a] for a in (X, Y, Z) if a != self.axis))

    @property
    def dominance(self) -> float:
        return self.travel / max(self.off_axis, 1.0)

    @property
    def peak_speed(self) -> float:
        """Highest speed along the stroke's direction, mm/s."""
        return max(float(self.direction * s.v[self.axis]) for s in self.samples)

    def core(self, fraction: float, speed_mm_s: float, gap_s: float = 0.06) -> "Stroke":
        """The part of the stroke moving faster than `fraction` of its peak speed or `speed_mm_s`,
        whichever is lower: the gesture proper, without the slow start of an arc or the settling at
        its end (the absolute bound keeps a stroke whole when a frame or two catch a very fast flick).
        Samples more than `gap_s` apart mean frames where the hand was not found."""
        threshold = min(fraction * self.peak_speed, speed_mm_s)
        fast = [i for i, s in enumerate(self.samples) if self.direction * s.v[self.axis] >= threshold]
        if not fast:
            return self
        first = fast[0]
        before = self.samples[first - 1] if first > 0 else None
        if before is not None and (self.samples[first].t - before.t > gap_s or before.t == before.seen_since):
            first -= 1  # the fast motion began where the hand was last seen, or seen again (no speed of its own)
        return Stroke(self.axis, self.direction, self.samples[first: fast[-1] + 1])

    @property
    def body_speed(self) -> float:
        """Fastest vertical speed of the torso during the stroke, mm/s (squatting, sitting, jumping)."""
        return max(abs(s.body_vy) for s in self.samples)

    @property
    def lowest(self) -> float:
        """Lowest height of the hand over the stroke, relative to the torso, mm."""
        return min(float(s.p[Y]) for s in self.samples)

    @property
    def highest(self) -> float:
        """Highest height of the hand over the stroke, relative to the torso, mm."""
        return max(float(s.p[Y]) for s in self.samples)


class AxisStrokes:
    """Segments one axis of a stream of samples into strokes, with a hysteresis and a stop time."""

    def __init__(self, axis: int, hysteresis_mm: float, stop_s: float) -> None:
        self.axis, self.hysteresis, self.stop_s = axis, hysteresis_mm, stop_s
        self.direction = 0
        self._samples: list[Sample] = []
        self._extreme = 0  # index in _samples of the furthest point reached in `direction`
        self._advanced_at = 0.0  # when the extreme last moved on by half the hysteresis or more
        self._advanced_value = 0.0

    def current(self) -> Stroke | None:
        """The stroke under way, from its start to the newest sample (None while the hand idles)."""
        if self.direction == 0:
            return None
        return Stroke(self.axis, self.direction, tuple(self._samples))

    def update(self, s: Sample) -> Stroke | None:
        """Add a sample; returns the stroke that this sample showed to be finished, if any."""
        a, h = self.axis, self.hysteresis
        self._samples.append(s)
        x = float(s.p[a])
        if self.direction == 0:
            values = [float(q.p[a]) for q in self._samples]
            lo, hi = int(np.argmin(values)), int(np.argmax(values))
            if x - values[lo] > h:
                self._begin(+1, lo)
            elif values[hi] - x > h:
                self._begin(-1, hi)
            else:  # idle: only the recent past can be where the next stroke starts
                self._samples = [q for q in self._samples if s.t - q.t <= 3 * self.stop_s]
            return None
        d = self.direction
        ext = float(self._samples[self._extreme].p[a])
        if d * (x - ext) > 0:
            self._extreme = len(self._samples) - 1
            if d * (x - self._advanced_value) >= h / 2:
                self._advanced_at, self._advanced_value = s.t, x
        elif d * (ext - x) > h:  # reversed: the stroke ended at its extreme, the next starts there
            done = self._finish()
            self._begin(-d, 0)
            return done
        if s.t - self._advanced_at > self.stop_s:  # stopped (or crawling) short of reversing
            done = self._finish()
            self.direction = 0
            return done
        return None

    def _begin(self, direction: int, start: int) -> None:
        self._samples = self._samples[start:]
        self.direction = direction
        self._extreme = len(self._samples) - 1
        q = self._samples[self._extreme]
        self._advanced_at, self._advanced_value = q.t, float(q.p[self.axis])

    def _finish(self) -> Stroke:
        done = Stroke(self.axis, self.direction, tuple(self._samples[: self._extreme + 1]))
        self._samples = self._samples[self._extreme:]
        return done
