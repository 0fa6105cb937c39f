"""`star-trail`: sparks that stream from every tracked hand, drift and fade (an ISSv2 effect), in
one colour or each performer's sparks in their user's colour."""
from __future__ import annotations

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from effects.gl import Particles, Sprites
from host import Effect, Frame, Stage, user_colour
from host.options import Color


class StarTrailOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    rate: float = Field(120.0, ge=0, le=5000, description="sparks per second per hand")
    life: float = Field(1.2, gt=0, le=10, description="seconds a spark lives")
    speed: float = Field(0.08, ge=0, description="spark speed, output heights per second")
    size: float = Field(0.012, gt=0, le=0.2, description="spark radius, fraction of the output height")
    color: Color = (1.0, 0.85, 0.5)
    by_user: bool = Field(False, description="each hand's sparks in its user's colour (host.user_colour) "
                          "instead of `color`")
    max_sparks: int = Field(3000, ge=1, le=100000)


class StarTrail(Effect):
    name = "star-trail"
    Options = StarTrailOptions
    renders = True
    keystone_aware = True

    def setup(self, stage: Stage) -> None:
        super().setup(stage)
        self.sparks = Particles(self.options.max_sparks)
        self.sprites = Sprites(stage.ctx, softness=0.9)
        # hand id -> (where on the stage, its sparks' colour)
        self.hands: dict[int, tuple[tuple[float, float], tuple[float, float, float]]] = {}
        self.rng = np.random.default_rng(7)
        self._debt = 0.0  # fractional sparks carried to the next frame

    def on_frame(self, frame: Frame) -> None:
        if frame.depth is None:
            return
        o = self.options
        self.hands = {}
        for h in frame.hands:
            if h.in_view and h.position[2] > 0:
                colour = user_colour(h.user_id) if o.by_user else o.color
                self.hands[h.id] = (self.stage.to_stage(h.position, frame.depth), colour)

    def render(self, target) -> None:
        o, h = self.options, target.size[1]
        dt = min(target.dt, 0.1)
        self.sparks.step(dt, drag=0.6, gravity=0.05 * h)
        self._debt += o.rate * dt
        count, self._debt = int(self._debt), self._debt % 1.0
        for pos, colour in self.hands.values():
            if count:
                angle = self.rng.uniform(0, 2 * np.pi, count)
                speed = o.speed * h * self.rng.uniform(0.2, 1.0, count)
                vel = np.c_[np.cos(angle), np.sin(angle)] * speed[:, None]
                tint = np.clip(np.asarray(colour) * self.rng.uniform(0.7, 1.3, (count, 1)), 0, 1)
                self.sparks.spawn(pos, vel, o.life * self.rng.uniform(0.5, 1.0, count), o.size * h, tint)
        self.sparks.draw(self.sprites, target)

    def close(self) -> None:
        if hasattr(self, "sprites"):
            self.sprites.release()
