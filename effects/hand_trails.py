"""`hand-trails`: the thesis' integrated sample application: a coloured point per tracked hand
with a trail of its last 20 positions, drawn where the hand is on the stage. Each hand takes its
user's colour (host.user_colour), so two performers' hands tell apart; the thesis coloured by
hand id, which `by_user = false` keeps."""
from __future__ import annotations

from collections import deque

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from effects.gl import Sprites
from host import Effect, Frame, Hand, Stage, user_colour
from host.options import Color

PALETTE: tuple[tuple[float, float, float], ...] = ((1.0, 0.25, 0.2), (0.2, 0.9, 0.3), (0.25, 0.5, 1.0),
                                                   (1.0, 0.85, 0.1), (0.9, 0.3, 1.0), (0.1, 0.9, 0.9))


class HandTrailsOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    length: int = Field(20, ge=1, le=1000, description="positions kept per hand (sensor frames)")
    size: float = Field(0.02, gt=0, le=0.5, description="point radius, fraction of the output height")
    by_user: bool = Field(True, description="each hand in its user's colour (host.user_colour); "
                          "false: `colors` by hand id")
    colors: list[Color] = Field(default_factory=lambda: list(PALETTE), min_length=1,
                                description="one colour per hand id, cycled, when not by user")


class HandTrails(Effect):
    name = "hand-trails"
    Options = HandTrailsOptions
    renders = True
    keystone_aware = True

    def setup(self, stage: Stage) -> None:
        super().setup(stage)
        self.trails: dict[int, deque[tuple[float, float]]] = {}
        self.colours: dict[int, tuple[float, float, float]] = {}  # hand id -> its colour now
        self.sprites = Sprites(stage.ctx, softness=0.25)

    def on_frame(self, frame: Frame) -> None:
        if frame.depth is None:
            return
        seen = set()
        for hand in frame.hands:
            if not hand.in_view or hand.position[2] <= 0:
                continue
            seen.add(hand.id)
            trail = self.trails.setdefault(hand.id, deque(maxlen=self.options.length))
            trail.append(self.stage.to_stage(hand.position, frame.depth))
            self.colours[hand.id] = self._colour(hand)
        for gone in self.trails.keys() - seen:
            del self.trails[gone], self.colours[gone]

    def _colour(self, hand: Hand) -> tuple[float, float, float]:
        if self.options.by_user:
            return user_colour(hand.user_id)
        return self.options.colors[hand.id % len(self.options.colors)]

    def render(self, target) -> None:
        centers, radii, rgba = [], [], []
        head = self.options.size * target.size[1]
        for hand_id, trail in self.trails.items():
            n = len(trail)
            ramp = np.arange(1, n + 1) / n  # oldest -> newest
            color = self.colours[hand_id]
            centers.append(np.asarray(trail))
            radii.append(head * np.where(ramp == 1.0, 1.0, 0.25 + 0.45 * ramp))
            rgba.append(np.c_[np.tile(color, (n, 1)), np.where(ramp == 1.0, 1.0, 0.2 + 0.6 * ramp)])
        if centers:
            self.sprites.draw(target, np.concatenate(centers), np.concatenate(radii), np.concatenate(rgba))

    def close(self) -> None:
        if hasattr(self, "sprites"):
            self.sprites.release()
