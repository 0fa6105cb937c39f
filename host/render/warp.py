"""The keystone: the stage texture drawn onto the output as a quad whose corners sit where the
profile says (`output.keystone`).

Vertices carry homogeneous clip coordinates, so the GPU's perspective-correct interpolation
applies the exact four-corner homography to every pixel in this one pass.
"""
from __future__ import annotations

import moderngl
import numpy as np

from host.render.calibration import UNIT_SQUARE, homography

STRIP = np.array([(0, 0), (1, 0), (0, 1), (1, 1)], np.float64)  # unit square as a triangle strip
VERTEX = """
#version 330
in vec3 in_pos;   // homogeneous clip position
in vec2 in_uv;
out vec2 uv;
void main() { uv = in_uv; gl_Position = vec4(in_pos.xy, 0.0, in_pos.z); }
"""
FRAGMENT = """
#version 330
uniform sampler2D stage;
in vec2 uv;
out vec4 color;
void main() { color = vec4(texture(stage, uv).rgb, 1.0); }
"""


def keystone_vertices(corners: list[tuple[float, float]]) -> np.ndarray:
    """(4, 5) float32 rows `x y w u v` for a triangle strip: clip position, texture coordinate.

    `corners` (top-left, top-right, bottom-right, bottom-left; output fractions, y down) are
    where the stage's corners land.
    """
    ndc = [(2 * x - 1, 1 - 2 * y) for x, y in corners]
    k = homography(UNIT_SQUARE, ndc)  # unit square (v down) -> clip space (y up)
    pos = np.c_[STRIP, np.ones(4)] @ k.T
    pos /= np.abs(pos[:, 2:3]).max()  # any positive scale is the same homography
    uv = np.c_[STRIP[:, 0], 1 - STRIP[:, 1]]  # texture t = 1 is the stage's top row
    return np.c_[pos, uv].astype("f4")


class Keystone:
    """Owns the stage texture the effects draw on, and draws it warped onto the output."""

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int], corners: list[tuple[float, float]]) -> None:
        self.ctx = ctx
        self.texture = ctx.texture(size, 4)
        self.texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
        self.texture.repeat_x = self.texture.repeat_y = False
        self.stage = ctx.framebuffer([self.texture])
        self.prog = ctx.program(vertex_shader=VERTEX, fragment_shader=FRAGMENT)
        self.vbo = ctx.buffer(keystone_vertices(corners).tobytes())
        self.vao = ctx.vertex_array(self.prog, [(self.vbo, "3f 2f", "in_pos", "in_uv")])

    def set_corners(self, corners: list[tuple[float, float]]) -> None:
        self.vbo.write(keystone_vertices(corners).tobytes())

    def draw(self, output: moderngl.Framebuffer) -> None:
        output.use()
        self.ctx.enable_only(moderngl.NOTHING)
        output.clear(0.0, 0.0, 0.0, 1.0)
        self.texture.use(0)
        self.vao.render(moderngl.TRIANGLE_STRIP)

    def release(self) -> None:
        for obj in (self.vao, self.vbo, self.prog, self.stage, self.texture):
            obj.release()
