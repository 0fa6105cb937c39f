"""The tracker's anatomy is an adult's; a child's is that scaled down by the child's height.

The body, hand and skeleton constants in mm (a chest's width, the shoulders below the crown, the
spine below the shoulders, an arm's thickness and length, a palm) describe an adult. Adults'
proportions vary less than the tolerances those constants carry, so everyone `ADULT_MIN_HEIGHT_MM`
tall or taller gets them as they are. A shorter performer, a child, gets every length scaled by
their height over that (and every area by its square): with an adult's spine 530 mm below the head,
a 1.2 m child's torso was placed at their hips and nothing but a wave was ever recognised.

The height is the crown's above the floor plane the segmenter found (a hand raised over the head
is no crown); without a floor in view, the crown's above the feet when they are in view (a
recording with its background removed; trunk.py says when the bottom of a silhouette is feet).
With neither (a camera pointing level at a wall, legs cut off by the picture) no height is known
and the adult's constants stay. The first crown sets the scale: a scale that changes moves the
body frame at once (at 0.86 the spine joint is placed 83 mm nearer the crown), which the
recogniser reads as the body moving and vetoes a swipe under way, so it had better change before
the performer starts than ten crowns in (a clip's performer starts within half a second). What it
cannot tell: a seated adult is as tall as a child; and a floor plane fitted askew (a child 1.8 m
from the camera, the plane tilted 9 degrees through their legs) makes a 1.1 m child 1.27 m.
"""
from __future__ import annotations

from collections import deque
from typing import Generic, TypeVar

import numpy as np
from pydantic import BaseModel

from backends.engine.quantiles import percentile

ADULT_MIN_HEIGHT_MM = 1500.0  # no shorter adult's anatomy is scaled
HEIGHT_FRAMES = 90  # crowns remembered: 3 s at 30 Hz
MIN_SCALE = 0.5  # a child of 0.75 m; anything smaller is a crouch that lasted, not a body
STEP = 0.02  # the scale moves in steps this fine (the options are rebuilt only when it moves)

Options = TypeVar("Options", bound=BaseModel)


class Stature:
    """How tall the performer stands, from their crown's recent heights above the floor, and the
    scale of their anatomy that follows."""

    def __init__(self) -> None:
        self._heights: deque[float] = deque(maxlen=HEIGHT_FRAMES)
        self.scale = 1.0

    def add(self, height_mm: float) -> None:
        self._heights.append(height_mm)
        heights = np.fromiter(self._heights, float, len(self._heights))
        standing = float(percentile(heights, 90))  # a crouch, a bow or a seat for a moment
        scale = min(max(standing / ADULT_MIN_HEIGHT_MM, MIN_SCALE), 1.0)
        self.scale = round(scale / STEP) * STEP


class Anatomy(Generic[Options]):
    """An adult's options, and the same scaled for the performer at hand (rebuilt when the scale moves)."""

    def __init__(self, adult: Options) -> None:
        self.adult = adult
        self._scale, self._options = 1.0, adult

    def at(self, scale: float) -> Options:
        if scale != self._scale:
            self._scale, self._options = scale, scaled(self.adult, scale)
        return self._options


def scaled(options: Options, scale: float) -> Options:
    """`options` with every length (`*_mm`, or a range of them) times `scale` and every area (`*_m2`)
    times its square."""
    if scale == 1.0:
        return options
    update = {}
    for name in type(options).model_fields:
        if name.endswith(("_mm", "_m2")):
            factor, value = (scale if name.endswith("_mm") else scale * scale), getattr(options, name)
            update[name] = tuple(v * factor for v in value) if isinstance(value, tuple) else value * factor
    return options.model_copy(update=update)
