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
uniform sampler2D image;   // the user mask (1 = performer), or depth in metres (0 = no reading)
uniform float near;        // depth band, metres: used when the image is depth
uniform float far;
uniform vec3 tint;
uniform float alpha;
in vec2 uv;
out vec4 color;
void main() {
    float v = texture(image, uv).r;
    float inside = MASK ? step(0.5, v) : float(v >= near && v <= far);
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
        # One program per input, so each pixel fetches one texture (llvmpipe pays per fetch).
        self.quads = {kind: DepthQuad(stage.ctx, FRAGMENT.replace("MASK", kind)) for kind in ("true", "false")}
        o = self.options
        for quad in self.quads.values():
            prog = quad.prog
            for name, value in (("near", o.near_mm / 1000), ("far", o.far_mm / 1000), ("tint", o.color), ("alpha", o.alpha)):
                if prog.get(name, None) is not None:
                    prog[name].value = value

    def render(self, target) -> None:
        mask = target.mask_texture()
        image = mask if mask is not None else target.depth_texture()
        if image is not None:
            quad = self.quads["true" if mask is not None else "false"]
            quad.draw(target, self.stage, target.frame.depth, {"image": image})

    def close(self) -> None:
        for quad in getattr(self, "quads", {}).values():
            quad.release()
