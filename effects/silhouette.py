"""`silhouette`: the performers' pixels, each in their user's colour, drawn where the stage puts them.

Uses the backend's user labels (`Frame.user_labels`: one image, each pixel its user's id) when it
has them, else its user mask (`Frame.user_mask`, every performer in `color`), else every pixel
whose depth lies in the band near_mm..far_mm (the performer standing in front of an empty stage).
Whichever it is, one texture per sensor frame is uploaded and the colour is looked up in the
shader, so two dancers cost what one does.
"""
from __future__ import annotations

import moderngl
import numpy as np
from pydantic import BaseModel, ConfigDict, Field, model_validator

from effects.gl import DepthQuad
from host import Effect, Stage, user_colour
from host.options import Color

FRAGMENT = """
#version 330
#define LABELS 0
#define MASK 1
#define DEPTH 2
uniform sampler2D image;   // user labels (r * 255 = user id), the user mask (1 = performer), or depth in metres
uniform sampler2D palette; // labels: 256 x 1, entry n the colour of user n (alpha 0 for nobody)
uniform float near;        // depth band, metres: used when the image is depth
uniform float far;
uniform vec3 tint;
uniform float alpha;
in vec2 uv;
out vec4 color;
void main() {
    float v = texture(image, uv).r;
    vec4 c = vec4(tint, 1.0);
    if (KIND == LABELS) {
        c = texture(palette, vec2(v * (255.0 / 256.0) + 0.5 / 256.0, 0.5));  // entry round(v * 255)
    } else if (KIND == MASK) {
        c.a = step(0.5, v);
    } else {
        c.a = float(v >= near && v <= far);
    }
    float a = alpha * c.a;
    color = vec4(c.rgb * a, a);
}
"""
KINDS = ("LABELS", "MASK", "DEPTH")


def palette(tint: tuple[float, float, float] | None) -> np.ndarray:
    """(1, 256, 4) uint8: entry n the colour of user n (host.user_colour), or `tint` for every
    user; entry 0 (nobody) transparent. A texture lookup costs llvmpipe less than picking from a
    uniform array by an integer id."""
    rgba = np.zeros((1, 256, 4), np.uint8)
    for user in range(1, 256):
        rgba[0, user] = np.round(np.r_[tint if tint is not None else user_colour(user), 1.0] * 255)
    return rgba


class SilhouetteOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    color: Color = Field((0.2, 0.6, 1.0), description="the performers' colour when not by user")
    by_user: bool = Field(True, description="each performer in their user's colour (host.user_colour) when the "
                          "backend labels users; false: everyone in `color`")
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
        self.quads = {kind: DepthQuad(stage.ctx, FRAGMENT.replace("KIND", kind)) for kind in KINDS}
        o = self.options
        values = {"near": o.near_mm / 1000, "far": o.far_mm / 1000, "tint": o.color, "alpha": o.alpha}
        for quad in self.quads.values():
            for name, value in values.items():
                if quad.prog.get(name, None) is not None:  # the driver drops unused uniforms
                    quad.prog[name].value = value
        self.palette = stage.ctx.texture((256, 1), 4, palette(None if o.by_user else o.color).tobytes())
        self.palette.filter = (moderngl.NEAREST, moderngl.NEAREST)

    def render(self, target) -> None:
        if target.frame is None or target.frame.depth is None:
            return  # no image to place the pixels by
        for kind, image in (("LABELS", target.labels_texture), ("MASK", target.mask_texture),
                            ("DEPTH", target.depth_texture)):
            texture = image()
            if texture is not None:
                textures = {"image": texture, "palette": self.palette}
                self.quads[kind].draw(target, self.stage, target.frame.depth, textures)
                return

    def close(self) -> None:
        for quad in getattr(self, "quads", {}).values():
            quad.release()
        if hasattr(self, "palette"):
            self.palette.release()
