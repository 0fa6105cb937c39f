"""The One Euro filter (Casiez, Roussel, Vogel, CHI 2012) on 3-D positions in millimetres.

Why this filter: a hand at rest needs heavy smoothing (depth noise is several mm per frame), a
hand in a swipe needs almost none (lag would delay and shrink the gesture). The One Euro filter
raises its cutoff with speed, so it does both with two parameters.
"""
from __future__ import annotations

import math

import numpy as np
from pydantic import BaseModel, ConfigDict, Field


class SmoothingOptions(BaseModel):
    """One Euro parameters. Cutoffs in hertz; `beta` in hertz per (mm/s) of speed."""

    model_config = ConfigDict(extra="forbid")
    enabled: bool = True
    min_cutoff_hz: float = Field(2.0, gt=0, description="cutoff at rest: lower = smoother, more lag")
    beta: float = Field(0.03, ge=0, description="cutoff increase per mm/s of speed: higher = less lag when fast")
    d_cutoff_hz: float = Field(1.0, gt=0, description="cutoff of the speed estimate")


def _alpha(cutoff_hz: float, dt: float) -> float:
    tau = 1.0 / (2.0 * math.pi * cutoff_hz)
    return 1.0 / (1.0 + tau / dt)


class OneEuroFilter:
    """Filters one stream of vectors sampled at irregular times (seconds)."""

    def __init__(self, options: SmoothingOptions) -> None:
        self.options = options
        self._t: float | None = None
        self._x: np.ndarray | None = None
        self._dx = np.zeros(3)

    def __call__(self, t: float, x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=np.float64)
        if not self.options.enabled:
            return x
        if self._x is None or self._t is None:
            self._x, self._t = x, t
            return x
        if t <= self._t:  # the same instant again (or a clock that went back): nothing new to filter
            return self._x
        # On Python floats: a 3-vector's few operations cost less than as numpy calls (the same
        # IEEE arithmetic, element by element; the norm summed in numpy's order).
        dt = t - self._t
        o = self.options
        new, last, speed = x.tolist(), self._x.tolist(), self._dx.tolist()
        alpha = _alpha(o.d_cutoff_hz, dt)
        speed = [v + alpha * ((n - p) / dt - v) for n, p, v in zip(new, last, speed)]
        cutoff = o.min_cutoff_hz + o.beta * math.sqrt(sum(v * v for v in speed))
        alpha = _alpha(cutoff, dt)
        self._dx = np.array(speed)
        self._x = np.array([p + alpha * (n - p) for n, p in zip(new, last)])
        self._t = t
        return self._x

    @property
    def velocity(self) -> np.ndarray:
        """The smoothed speed estimate (units per second), zero until two samples arrived."""
        return self._dx
