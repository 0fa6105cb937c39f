"""`hand-glow`: a soft light on each hand that flares when the performer does a gesture."""
from __future__ import annotations

import moderngl
import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from host import Effect, Frame, Gesture, GestureState, Stage, hookimpl
from host.options import Color

VERTEX = """
#version 330
uniform mat3 to_clip;   // output pixels -> clip space (the host's target.to_clip, keystone included)
uniform vec2 center;    // output pixels, y down
uniform float radius;   // pixels
in vec2 corner;         // -1..1
out vec2 local;
void main() {
    local = corner;
    vec3 p = to_clip * vec3(center + corner * radius, 1.0);
    gl_Position = vec4(p.xy, 0.0, p.z);
}
"""
FRAGMENT = """
#version 330
uniform vec3 color;
in vec2 local;
out vec4 frag;
void main() {
    float a = exp(-4.0 * dot(local, local));   // a soft Gaussian spot
    frag = vec4(color * a, a);                 // premultiplied, as the host composites
}
"""


class HandGlowOptions(BaseModel):
    """What a profile may set under [[effects]] name = "hand-glow"; anything else is an error."""

    model_config = ConfigDict(extra="forbid")
    gestures: list[str] = ["wave", "click", "swipe_left", "swipe_right", "swipe_up", "swipe_down", "hand_raise"]
    color: Color = (1.0, 0.6, 0.2)
    radius: float = Field(0.08, gt=0, le=1, description="glow radius, fraction of the output height")
    flare: float = Field(0.6, ge=0, le=5, description="seconds a gesture's flare takes to fade")


class HandGlow(Effect):
    name = "hand-glow"
    Options = HandGlowOptions
    renders = True

    def setup(self, stage: Stage) -> None:
        """Once, before the show: `stage.size` is the output in pixels, `stage.ctx` the moderngl
        context (None when nothing is drawn)."""
        super().setup(stage)
        self.count = 0
        self.hands: dict[int, tuple[float, float, float]] = {}
        self.depth = None
        self.flares: dict[int, float] = {}  # hand id -> seconds of flare left
        self.prog = None
        if stage.ctx is not None:
            ctx = stage.ctx
            self.prog = ctx.program(vertex_shader=VERTEX, fragment_shader=FRAGMENT)
            self.quad = ctx.buffer(np.array([-1, -1, 1, -1, -1, 1, 1, 1], "f4").tobytes())
            self.vao = ctx.vertex_array(self.prog, [(self.quad, "2f", "corner")])

    def on_gesture(self, gesture: Gesture) -> None:
        """Every gesture event, exactly once, in order (IN_PROGRESS, then COMPLETE)."""
        if gesture.state is GestureState.COMPLETE and gesture.name in self.options.gestures:
            self.count += 1
            self.flares[gesture.hand_id] = self.options.flare
            print(f"hand-glow: {gesture.name} by the {gesture.side.value} hand ({self.count} so far)", flush=True)

    def on_frame(self, frame: Frame) -> None:
        """The newest frame: hands in millimetres (x right, y up, z away from the camera)."""
        self.hands = {hand.id: hand.position for hand in frame.hands}
        self.depth = frame.depth

    def render(self, target) -> None:
        """Draw this effect's layer: `target.size` pixels, `target.dt` seconds since the last frame."""
        if self.prog is None or self.depth is None:
            return
        self.prog["to_clip"].write(np.asarray(target.to_clip, "f4").T.tobytes())  # GLSL is column-major
        for hand_id, position in self.hands.items():
            flare = self.flares.get(hand_id, 0.0) / max(self.options.flare, 1e-6)
            self.prog["center"] = self.stage.to_stage(position, self.depth)
            self.prog["radius"] = self.options.radius * target.size[1] * (1.0 + 2.0 * flare)
            self.prog["color"] = tuple(min(1.0, c + flare) for c in self.options.color)
            self.vao.render(moderngl.TRIANGLE_STRIP)  # blending is the host's: the profile's `blend`
        self.flares = {h: t - target.dt for h, t in self.flares.items() if t > target.dt}

    def close(self) -> None:
        """Once, after the show: release what setup acquired."""
        if self.prog is not None:
            for obj in (self.vao, self.quad, self.prog):
                obj.release()


@hookimpl
def register_effects(register):
    register(HandGlow)
