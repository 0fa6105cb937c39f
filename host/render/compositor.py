"""The stage: effects draw in profile order, each with its blend mode and opacity.

llvmpipe (Mesa's CPU rasteriser, what runs without a GPU) pays for every pixel of every pass,
so the stage keeps passes few: an effect at full opacity draws straight onto the stage with its
blend mode set as the GL blend function, touching only the pixels it covers (a sprite costs its
own square, not a full-screen layer). Only an effect with opacity < 1 gets a layer texture of its
own, blended onto the stage in one extra pass. The keystone costs nothing when every effect
draws through `target.to_clip` (their class says `keystone_aware = True`): the homography is in
that matrix and shapes land warped on the output directly. Otherwise the stage is a texture that
`warp.py` draws onto the output in one last pass.

Effects draw premultiplied colour (rgb * alpha, alpha) and leave the blend state as the host
set it; an effect's own overlapping shapes combine with its blend mode too.

Filters read the show so far: `target.below()` copies the stage as composited up to this layer
into a texture (one blit, only for the effects that ask). A layer group (effects N..M) that a
later effect reads with `target.layers(N, M)` is drawn into a texture of its own instead of onto
the stage, so that effect (a transition) can mix it with what is below; inside a group,
`below()` is the group drawn so far.
"""
from __future__ import annotations

import moderngl
import numpy as np

from host.model import Frame
from host.render.textures import FrameTextures


def pixels_to_clip(size: tuple[int, int], keystone: np.ndarray | None = None) -> np.ndarray:
    """3x3 from output pixels (y down) to clip space (y up), through a keystone (pixels -> pixels)."""
    w, h = size
    m = np.array([[2 / w, 0, -1], [0, -2 / h, 1], [0, 0, 1]], np.float64)
    return m if keystone is None else m @ keystone


# (source factor, destination factor) for premultiplied colour s over the stage d.
BLEND_FUNCS = {
    "normal": (moderngl.ONE, moderngl.ONE_MINUS_SRC_ALPHA),   # s + d (1 - sa)
    "add": (moderngl.ONE, moderngl.ONE),                      # s + d
    "screen": (moderngl.ONE, moderngl.ONE_MINUS_SRC_COLOR),   # s + d (1 - s) = 1 - (1 - s)(1 - d)
    "multiply": (moderngl.DST_COLOR, moderngl.ONE_MINUS_SRC_ALPHA),  # s d + d (1 - sa)
}

QUAD_VERTEX = """
#version 330
in vec2 in_pos;
out vec2 uv;
void main() { uv = in_pos * 0.5 + 0.5; gl_Position = vec4(in_pos, 0.0, 1.0); }
"""
OPACITY_FRAGMENT = """
#version 330
uniform sampler2D layer;
uniform float opacity;
in vec2 uv;
out vec4 color;
void main() { color = texture(layer, uv) * opacity; }
"""


class Layer:
    """What an effect's `render(target)` gets: where to draw, already bound, blending set.

    Draw premultiplied colour in output pixels (x right, y down from the top-left, `size`),
    through clip space. `frame` is the newest Frame (None before the first); `time` and `dt` are
    seconds since the show's first render and since the previous one. `to_clip` is the 3x3 matrix
    from output pixels to homogeneous clip space (gl_Position = vec4(p.xy, 0, p.z) with
    p = to_clip * vec3(x, y, 1)): it includes the keystone when the stage is drawn in place.
    `depth_texture()`, `mask_texture()` and `labels_texture()` give the frame's depth (R32F,
    metres, 0 = no reading), user mask (R8, 1 = performer) and user labels (R8: round(r * 255) is
    0 for nobody, else the user id; None when the backend labels no users), each uploaded at most
    once per sensor frame and shared by all effects; image row 0 sits at texture t = 1. `fbo` is the framebuffer to draw into (an effect that renders elsewhere first
    must bind it again with `use()`).
    """

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int], textures: FrameTextures,
                 compositor: "Compositor | None" = None) -> None:
        self.ctx = ctx
        self.size = size
        self._compositor = compositor
        self.fbo: moderngl.Framebuffer | None = None
        self.to_clip = pixels_to_clip(size)
        self.blend = "normal"
        self._textures = textures
        self.frame: Frame | None = None
        self.time = 0.0
        self.dt = 0.0

    def use(self) -> None:
        """Binds the framebuffer and the blending again (after drawing into a texture of your own)."""
        self.fbo.use()
        self.ctx.enable_only(moderngl.BLEND)
        self.ctx.blend_equation = moderngl.FUNC_ADD
        self.ctx.blend_func = BLEND_FUNCS[self.blend]

    def depth_texture(self) -> moderngl.Texture | None:
        return self._textures.depth()

    def mask_texture(self) -> moderngl.Texture | None:
        return self._textures.mask()

    def labels_texture(self) -> moderngl.Texture | None:
        return self._textures.labels()

    def below(self) -> moderngl.Texture:
        """Everything composited below this layer (RGBA, t = 1 at the top), copied once per call."""
        texture = self._compositor.copy_stage()
        self.use()
        return texture

    def layers(self, first: int, last: int) -> moderngl.Texture:
        """Effects first..last (profile indices) as drawn apart this frame (transparent where empty)."""
        return self._compositor.group(first, last).color_attachments[0]


class Compositor:
    """Runs the effects' draws onto the stage framebuffer in order; see the module docstring."""

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int], textures: FrameTextures) -> None:
        self.ctx = ctx
        self.size = size
        self.prog = ctx.program(vertex_shader=QUAD_VERTEX, fragment_shader=OPACITY_FRAGMENT)
        self.vbo = ctx.buffer(np.array([-1, -1, 1, -1, -1, 1, 1, 1], "f4").tobytes())
        self.vao = ctx.vertex_array(self.prog, [(self.vbo, "2f", "in_pos")])
        self._layer_fbo: moderngl.Framebuffer | None = None  # shared by effects with opacity < 1
        self._below: moderngl.Texture | None = None
        self._groups: dict[tuple[int, int], moderngl.Framebuffer] = {}
        self.target = Layer(ctx, size, textures, self)

    def _translucent_fbo(self) -> moderngl.Framebuffer:
        if self._layer_fbo is None:
            self._layer_fbo = self.ctx.framebuffer([self.ctx.texture(self.size, 4)])
        return self._layer_fbo

    def begin(self, stage: moderngl.Framebuffer, frame: Frame | None, time: float, dt: float) -> None:
        stage.use()
        self.ctx.enable_only(moderngl.NOTHING)
        stage.clear(0.0, 0.0, 0.0, 1.0)
        self.stage = stage
        self.target.frame, self.target.time, self.target.dt = frame, time, dt

    def copy_stage(self) -> moderngl.Texture:
        if self._below is None:
            self._below = self.ctx.texture(self.size, 4)
            self._below.filter = (moderngl.LINEAR, moderngl.LINEAR)
            self._below.repeat_x = self._below.repeat_y = False
        self.ctx.copy_framebuffer(self._below, self.stage)
        return self._below

    def group(self, first: int, last: int) -> moderngl.Framebuffer:
        key = (first, last)
        if key not in self._groups:
            texture = self.ctx.texture(self.size, 4)
            texture.repeat_x = texture.repeat_y = False
            self._groups[key] = self.ctx.framebuffer([texture])
            self._groups[key].clear(0.0, 0.0, 0.0, 0.0)
        return self._groups[key]

    def open_group(self, first: int, last: int) -> None:
        """The next layers draw into group first..last (cleared) until `close_group()`."""
        self._main = self.stage
        self.stage = self.group(first, last)
        self.stage.clear(0.0, 0.0, 0.0, 0.0)

    def close_group(self) -> None:
        self.stage = self._main

    def before(self, blend: str, opacity: float) -> Layer:
        """Binds where the next effect draws: the stage itself, or a cleared layer if translucent."""
        target = self.target
        if opacity >= 1.0:
            target.fbo, target.blend = self.stage, blend
        else:
            target.fbo, target.blend = self._translucent_fbo(), "normal"
            target.fbo.use()
            target.fbo.clear(0.0, 0.0, 0.0, 0.0)
        target.use()
        return target

    def after(self, blend: str, opacity: float) -> None:
        """Blends a translucent effect's layer onto the stage."""
        if opacity >= 1.0:
            return
        self.stage.use()
        self.ctx.enable_only(moderngl.BLEND)
        self.ctx.blend_func = BLEND_FUNCS[blend]
        self._layer_fbo.color_attachments[0].use(0)
        self.prog["opacity"] = float(opacity)
        self.vao.render(moderngl.TRIANGLE_STRIP)

    def release(self) -> None:
        for fbo in self._groups.values():
            fbo.color_attachments[0].release()
            fbo.release()
        if self._below is not None:
            self._below.release()
        if self._layer_fbo is not None:
            self._layer_fbo.color_attachments[0].release()
            self._layer_fbo.release()
        for obj in (self.vao, self.vbo, self.prog):
            obj.release()
