"""Runs an ISF shader's passes: each PASSES entry with a TARGET draws into that buffer (its size
from WIDTH/HEIGHT, 8-bit or FLOAT, kept across frames), the last one draws the output.

A buffer that a pass both reads and writes (feedback) is two textures swapped after each pass,
so no pass samples the texture it renders into. Buffers use GL's orientation (t = 1 at the
top, as isf_FragNormCoord), like the host's depth and mask textures and the images given here.
"""
from __future__ import annotations

import datetime as dt
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import cv2
import moderngl
import numpy as np

from effects.gl import mat3_bytes
from effects.isf.glsl import glsl_name
from effects.isf.header import IMAGE_TYPES, IsfError, Pass, evaluate_size
from effects.isf.shader import IsfShader

IDENTITY = np.eye(3)
COPY_VERTEX = """#version 330
uniform mat3 issv_clip;
in vec2 issv_position;
out vec2 uv;
void main() { uv = issv_position * 0.5 + 0.5; vec3 p = issv_clip * vec3(issv_position, 1.0);
              gl_Position = vec4(p.xy, 0.0, p.z); }
"""
COPY_FRAGMENT = """#version 330
uniform sampler2D image;
uniform bool premultiplied;
in vec2 uv;
out vec4 color;
void main() { vec4 c = texture(image, uv); color = premultiplied ? c : vec4(c.rgb * c.a, c.a); }
"""


@dataclass
class Output:
    """Where the last pass draws: `bind()` makes it current (with its blending), `clip` maps the
    unit quad's clip space onto it (a keystone, or identity), `size` is its RENDERSIZE."""

    bind: Callable[[], None]
    size: tuple[int, int]
    clip: np.ndarray = field(default_factory=lambda: IDENTITY)


def clip_on(to_clip: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """Clip space -> the host's clip space through its `to_clip` (pixels, y down -> clip)."""
    w, h = size
    to_pixels = np.array([[w / 2, 0, w / 2], [0, -h / 2, h / 2], [0, 0, 1]], np.float64)
    return to_clip @ to_pixels


class Buffer:
    """A pass target: two same-size textures, `current` read while the other is drawn."""

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int], floating: bool) -> None:
        self.size, self.floating = size, floating
        self.textures = [ctx.texture(size, 4, dtype="f4" if floating else "f1") for _ in range(2)]
        self.fbos = [ctx.framebuffer([t]) for t in self.textures]
        for tex, fbo in zip(self.textures, self.fbos):
            tex.filter = (moderngl.LINEAR, moderngl.LINEAR)
            tex.repeat_x = tex.repeat_y = False
            fbo.clear(0.0, 0.0, 0.0, 0.0)
        self.front = 0

    @property
    def current(self) -> moderngl.Texture:
        return self.textures[self.front]

    def draw_into(self) -> moderngl.Framebuffer:
        return self.fbos[1 - self.front]

    def bind(self) -> None:
        """Makes the texture not read this frame current, blending off."""
        fbo = self.draw_into()
        fbo.use()
        fbo.ctx.enable_only(moderngl.NOTHING)

    def swap(self) -> None:
        self.front = 1 - self.front

    def release(self) -> None:
        for obj in self.fbos + self.textures:
            obj.release()


class IsfRenderer:
    """One ISF shader on one GL context: `draw(values, images, output, ...)` runs all its passes."""

    def __init__(self, ctx: moderngl.Context, shader: IsfShader) -> None:
        self.ctx, self.shader, self.header = ctx, shader, shader.header
        passes = range(len(self.header.passes))
        self.progs = [shader.program(ctx, i) for i in passes] if shader.branches_on_pass else [shader.program(ctx)]
        self.copy = ctx.program(vertex_shader=COPY_VERTEX, fragment_shader=COPY_FRAGMENT)
        self.vbo = ctx.buffer(np.array([(-1, -1), (1, -1), (-1, 1), (1, 1)], "f4").tobytes())
        self.vaos = [ctx.vertex_array(prog, [(self.vbo, "2f", "issv_position")]) for prog in self.progs]
        self.copy_vao = ctx.vertex_array(self.copy, [(self.vbo, "2f", "issv_position")])
        self.blank = ctx.texture((1, 1), 4, np.zeros(4, "u1").tobytes())
        self.imported = {name: load_image(ctx, path) for name, path in self.header.imported.items()}
        self.buffers: dict[str, Buffer] = {}
        self.frame = 0
        self.image_names = [i.name for i in self.header.inputs if i.type in IMAGE_TYPES]
        self.image_names += [n for n in list(self.imported) + [p.target for p in self.header.passes if p.target]
                             + list(self.header.persistent) if n and n not in self.image_names]

    def set_values(self, prog: moderngl.Program, values: dict[str, Any]) -> None:
        for name, value in values.items():
            uniform = prog.get(glsl_name(name), None)
            kind = self.shader.inputs.get(name)
            if uniform is None or kind is None or kind in IMAGE_TYPES:
                continue  # unused by the shader (the compiler dropped it), or an image
            if kind in ("bool", "event"):
                value = bool(value)
            elif kind == "long":
                value = int(value)
            elif kind in ("color", "point2D"):
                value = tuple(float(v) for v in value)
            else:
                value = float(value)
            uniform.value = value

    def draw(self, values: dict[str, Any], images: dict[str, moderngl.Texture], output: Output,
             time: float, delta: float, sizes: dict[str, tuple[int, int]] | None = None) -> None:
        """All passes, then the output; `values` are the inputs' current values (sizes read them).
        `sizes`: images the shader sees at another size than their texture's (IMG_PIXEL, IMG_SIZE)."""
        numeric = {k: v for k, v in values.items() if isinstance(v, (int, float))}
        now = dt.datetime.now()
        midnight = now.hour * 3600 + now.minute * 60 + now.second + now.microsecond / 1e6
        for prog in self.progs:
            self.set_values(prog, values)
            set_uniform(prog, "TIME", time)
            set_uniform(prog, "TIMEDELTA", delta)
            set_uniform(prog, "FRAMEINDEX", self.frame)
            set_uniform(prog, "DATE", (float(now.year), float(now.month), float(now.day), midnight))
        for name, spec in self.header.persistent.items():
            self._buffer(spec, output.size, numeric)
        last = len(self.header.passes) - 1
        for index, spec in enumerate(self.header.passes):
            one = index if len(self.progs) > 1 else 0
            prog, vao = self.progs[one], self.vaos[one]
            set_uniform(prog, "PASSINDEX", index)
            buffer = self._buffer(spec, output.size, numeric) if spec.target else None
            if buffer is not None:
                buffer.bind()
                size, clip, premultiply = buffer.size, IDENTITY, False
            else:
                output.bind()
                size, clip, premultiply = output.size, output.clip, True
            set_uniform(prog, "RENDERSIZE", (float(size[0]), float(size[1])))
            set_uniform(prog, "issv_premultiply", premultiply)
            prog["issv_clip"].write(mat3_bytes(clip))
            self._bind_images(prog, images, sizes or {})
            vao.render(moderngl.TRIANGLE_STRIP)
            if buffer is not None:
                buffer.swap()
                if index == last:  # the output is the last pass's target: show it
                    output.bind()
                    self.show(buffer.current, output)
        self.frame += 1

    def show(self, texture: moderngl.Texture, output: Output, premultiplied: bool = False) -> None:
        """Draws a texture over the output (bound), premultiplying a straight-alpha one."""
        texture.use(0)
        self.copy["premultiplied"] = premultiplied
        self.copy["issv_clip"].write(mat3_bytes(output.clip))
        self.copy_vao.render(moderngl.TRIANGLE_STRIP)

    def _buffer(self, spec: Pass, base: tuple[int, int], values: dict[str, float]) -> Buffer:
        variables = {**values, "WIDTH": base[0], "HEIGHT": base[1]}
        size = tuple(max(1, int(evaluate_size(expr, variables))) if expr is not None else full
                     for expr, full in ((spec.width, base[0]), (spec.height, base[1])))
        old = self.buffers.get(spec.target)
        if old is not None and old.size == size and old.floating == spec.float:
            return old
        if old is not None:
            old.release()
        self.buffers[spec.target] = Buffer(self.ctx, size, spec.float)
        return self.buffers[spec.target]

    def _bind_images(self, prog: moderngl.Program, images: dict[str, moderngl.Texture],
                     sizes: dict[str, tuple[int, int]]) -> None:
        for unit, name in enumerate(self.image_names):
            texture = images.get(name) or (self.buffers[name].current if name in self.buffers else None) \
                or self.imported.get(name) or self.blank
            texture.use(unit)
            set_uniform(prog, glsl_name(name), unit)
            w, h = sizes.get(name) or texture.size
            set_uniform(prog, f"_{name}_imgSize", (float(w), float(h)))
            set_uniform(prog, f"_{name}_imgRect", (0.0, 0.0, float(w), float(h)))

    def release(self) -> None:
        for buffer in self.buffers.values():
            buffer.release()
        for obj in [*self.vaos, self.copy_vao, self.vbo, *self.progs, self.copy, self.blank, *self.imported.values()]:
            obj.release()


def set_uniform(prog: moderngl.Program, name: str, value: Any) -> None:
    """Sets a uniform the program uses (the compiler drops the others)."""
    uniform = prog.get(name, None)
    if uniform is not None:
        uniform.value = value


def load_image(ctx: moderngl.Context, path: Path) -> moderngl.Texture:
    """An image file as an RGBA texture, its first row at the top (t = 1)."""
    image = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if image is None:
        raise IsfError(f"{path}: cannot read this IMPORTED image (PNG, JPEG, ...)")
    if image.ndim == 2:
        image = cv2.cvtColor(image, cv2.COLOR_GRAY2RGBA)
    elif image.shape[2] == 3:
        image = cv2.cvtColor(image, cv2.COLOR_BGR2RGBA)
    else:
        image = cv2.cvtColor(image, cv2.COLOR_BGRA2RGBA)
    if image.dtype != np.uint8:
        image = (image / (math.pow(2, 8 * image.dtype.itemsize) - 1) * 255).astype(np.uint8)
    texture = ctx.texture((image.shape[1], image.shape[0]), 4, np.ascontiguousarray(image[::-1]).tobytes())
    texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
    texture.repeat_x = texture.repeat_y = False
    return texture
