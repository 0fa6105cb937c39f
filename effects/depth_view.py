"""`depth-view`: the depth image as a colour-mapped texture (the sample application's backdrop)."""
from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from effects.gl import DepthQuad
from host import Effect, Stage

FRAGMENT = """
#version 330
uniform sampler2D depth;   // metres, 0 = no reading
uniform float near;
uniform float far;
uniform int colormap;      // 0 gray (near = bright), 1 turbo
in vec2 uv;
out vec4 color;
vec3 turbo(float t) {      // a polynomial fit of Google's Turbo colour map
    const vec4 kr = vec4(0.13572138, 4.61539260, -42.66032258, 132.13108234);
    const vec4 kg = vec4(0.09140261, 2.19418839, 4.84296658, -14.18503333);
    const vec4 kb = vec4(0.10667330, 12.64194608, -60.58204836, 110.36276771);
    const vec2 kr2 = vec2(-152.94239396, 59.28637943);
    const vec2 kg2 = vec2(4.27729857, 2.82956604);
    const vec2 kb2 = vec2(-89.90310912, 27.34824973);
    vec4 v4 = vec4(1.0, t, t * t, t * t * t);
    vec2 v2 = v4.zw * v4.z;
    return vec3(dot(v4, kr) + dot(v2, kr2), dot(v4, kg) + dot(v2, kg2), dot(v4, kb) + dot(v2, kb2));
}
void main() {
    float d = texture(depth, uv).r;
    if (d <= 0.0) { color = vec4(0.0); return; }
    float t = clamp((d - near) / (far - near), 0.0, 1.0);
    vec3 rgb = colormap == 1 ? turbo(1.0 - t) : vec3(1.0 - 0.85 * t);
    color = vec4(clamp(rgb, 0.0, 1.0), 1.0);
}
"""


class DepthViewOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    near_mm: float = Field(500.0, gt=0, description="depth shown brightest / red")
    far_mm: float = Field(4500.0, gt=0, description="depth shown darkest / blue")
    colormap: Literal["gray", "turbo"] = "gray"

    @model_validator(mode="after")
    def _range(self) -> "DepthViewOptions":
        if self.far_mm <= self.near_mm:
            raise ValueError(f"far_mm ({self.far_mm}) must be greater than near_mm ({self.near_mm})")
        return self


class DepthView(Effect):
    name = "depth-view"
    Options = DepthViewOptions
    renders = True
    keystone_aware = True

    def setup(self, stage: Stage) -> None:
        super().setup(stage)
        self.quad = DepthQuad(stage.ctx, FRAGMENT)
        prog = self.quad.prog
        prog["near"], prog["far"] = self.options.near_mm / 1000, self.options.far_mm / 1000
        prog["colormap"] = 1 if self.options.colormap == "turbo" else 0

    def render(self, target) -> None:
        depth = target.depth_texture()
        if depth is not None:
            self.quad.draw(target, self.stage, target.frame.depth, {"depth": depth})

    def close(self) -> None:
        if hasattr(self, "quad"):
            self.quad.release()
