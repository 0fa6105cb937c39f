"""`silhouette`: the performer's pixels in one colour, drawn where the stage puts them.

Uses the backend's user mask (`Frame.user_mask`) when it has one, else every pixel whose depth
lies in the band near_mm..far_mm (the performer standing in front of an empty stage).
"""
from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field, model_validator

from effects.gl import DepthQuad
from host import Effect, Stage
from host.options import Color

FRAGMENT = """
#version 330
uniform sampler2D depth;   // metres, 0 = no reading
uniform sampler2D mask;    // 1 = performer
uniform bool use_mask;
uniform float near;
uniform float far;
uniform vec3 tint;
uniform float alpha;
in vec2 uv;
out vec4 color;
void main() {
    float d = texture(depth, uv).r;
    float inside = use_mask ? step(0.5, texture(mask, uv).r) : float(d >= near && d <= far);
    float a = alpha * inside;
    color = vec4(tint * a, a);
}
"""


class SilhouetteOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    color: Color = (0.2, 0.6, 1.0)
    alpha: float = Field(1.0, ge=0, le=1)
    near_mm: float = Field(500.0, gt=0, description="depth band used when the backend gives no mask")
    far_mm: float = Field(3500.0, gt=0)

    @model_validator(mode="after")
    def _range(self) -> "SilhouetteOptions":
        if self.far_mm <= self.near_mm:
            raise ValueError(f"far_mm ({self.far_mm}) must be greater than near_mm ({self.near_mm})")
        return self


class Silhouette(Effect):
    name = "silhouette"
    Options = SilhouetteOptions
    renders = True
    keystone_aware = True

    def setup(self, stage: Stage) -> None:
        super().setup(stage)
        self.quad = DepthQuad(stage.ctx, FRAGMENT)
        prog, o = self.quad.prog, self.options
        prog["near"], prog["far"] = o.near_mm / 1000, o.far_mm / 1000
        prog["tint"], prog["alpha"] = o.color, o.alpha

    def render(self, target) -> None:
        depth = target.depth_texture()
        if depth is None:
            return
        mask = target.mask_texture()
        self.quad.prog["use_mask"] = mask is not None
        self.quad.draw(target, self.stage, target.frame.depth, {"depth": depth, "mask": mask if mask is not None else depth})

    def close(self) -> None:
        if hasattr(self, "quad"):
            self.quad.release()
