"""`gesture-burst`: a burst of light where a chosen gesture happened, as each one completes."""
from __future__ import annotations

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, field_validator

from effects.gl import Particles, Sprites
from host import CANONICAL_GESTURES, DepthFrame, Effect, Frame, Gesture, GestureState, Stage
from host.options import Color


class GestureBurstOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    gesture: str = Field("any", description="a canonical gesture name (wave, click, swipe_left, ...) or any")
    color: Color = (1.0, 0.4, 0.8)
    sparks: int = Field(90, ge=1, le=5000, description="sparks per burst")
    life: float = Field(0.9, gt=0, le=10, description="seconds a burst lasts")
    speed: float = Field(0.45, gt=0, description="burst speed, output heights per second")
    size: float = Field(0.014, gt=0, le=0.2, description="spark radius, fraction of the output height")

    @field_validator("gesture")
    @classmethod
    def _known(cls, name: str) -> str:
        if name != "any" and name not in CANONICAL_GESTURES:
            raise ValueError(f"expected any or one of {', '.join(CANONICAL_GESTURES)}")
        return name


class GestureBurst(Effect):
    name = "gesture-burst"
    Options = GestureBurstOptions
    renders = True
    keystone_aware = True

    def setup(self, stage: Stage) -> None:
        super().setup(stage)
        self.sparks = Particles(20 * self.options.sparks)
        self.sprites = Sprites(stage.ctx, softness=0.8)
        self.depth: DepthFrame | None = None
        self.pending: list[Gesture] = []
        self.rng = np.random.default_rng(11)

    def on_frame(self, frame: Frame) -> None:
        self.depth = frame.depth if frame.depth is not None else self.depth

    def on_gesture(self, gesture: Gesture) -> None:
        if gesture.state is GestureState.COMPLETE and self.options.gesture in ("any", gesture.name):
            self.pending.append(gesture)

    def _burst(self, gesture: Gesture, height: int) -> None:
        o = self.options
        if self.depth is None or gesture.position[2] <= 0:
            return  # no depth image yet to place it with, or no position
        origin = self.stage.to_stage(gesture.position, self.depth)
        angle = np.linspace(0, 2 * np.pi, o.sparks, endpoint=False) + self.rng.uniform(0, 0.3)
        speed = o.speed * height * self.rng.uniform(0.6, 1.0, o.sparks)
        vel = np.c_[np.cos(angle), np.sin(angle)] * speed[:, None]
        self.sparks.spawn(origin, vel, o.life, o.size * height, o.color)

    def render(self, target) -> None:
        for gesture in self.pending:
            self._burst(gesture, target.size[1])
        self.pending.clear()
        self.sparks.step(min(target.dt, 0.1), drag=0.9)
        self.sparks.draw(self.sprites, target)

    def close(self) -> None:
        if hasattr(self, "sprites"):
            self.sprites.release()
