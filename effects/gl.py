"""Drawing helpers the built-in render effects share: the depth image drawn where the stage puts
it, soft round sprites, a small particle system, and a reduced-resolution offscreen image.

Everything draws premultiplied colour (rgb * alpha, alpha) in output pixels (x right, y down
from the top-left) through the target's `to_clip` matrix (which carries the keystone), with
homogeneous positions so that the keystone's perspective is exact; blending is left to the host,
which sets the effect's blend mode.
"""
from __future__ import annotations

import moderngl
import numpy as np

from host import DepthFrame, Stage


def plain_clip(size: tuple[int, int]) -> np.ndarray:
    """3x3 from pixels (y down) to clip space (y up), no keystone: for drawing into textures."""
    w, h = size
    return np.array([[2 / w, 0, -1], [0, -2 / h, 1], [0, 0, 1]], np.float64)


def mat3_bytes(m: np.ndarray) -> bytes:
    return np.asarray(m, "f4").T.tobytes()  # GLSL reads matrices column by column


DEPTH_VERTEX = """
#version 330
uniform mat3 to_clip;   // depth image (0..1, v down) -> clip space, homogeneous
in vec2 in_uv;
out vec2 uv;
void main() {
    vec3 p = to_clip * vec3(in_uv, 1.0);
    uv = vec2(in_uv.x, 1.0 - in_uv.y);  // image row 0 sits at the texture's top
    gl_Position = vec4(p.xy, 0.0, p.z);
}
"""


class UnitQuad:
    """A program drawn as one triangle strip over the unit square (its `in_uv`, 0..1, v down)."""

    def __init__(self, ctx: moderngl.Context, vertex_shader: str, fragment_shader: str) -> None:
        self.prog = ctx.program(vertex_shader=vertex_shader, fragment_shader=fragment_shader)
        strip = np.array([(0, 0), (1, 0), (0, 1), (1, 1)], "f4")
        self.vbo = ctx.buffer(strip.tobytes())
        self.vao = ctx.vertex_array(self.prog, [(self.vbo, "2f", "in_uv")])

    def release(self) -> None:
        for obj in (self.vao, self.vbo, self.prog):
            obj.release()


class DepthQuad(UnitQuad):
    """Draws a fragment shader over the depth image's footprint on the stage: stretched over the
    output, or through the camera-to-stage calibration so pixels land on the performer."""

    def __init__(self, ctx: moderngl.Context, fragment_shader: str) -> None:
        super().__init__(ctx, DEPTH_VERTEX, fragment_shader)

    def draw(self, target, stage: Stage, depth: DepthFrame, textures: dict[str, moderngl.Texture]) -> None:
        scale = np.diag([depth.width, depth.height, 1.0])
        m = target.to_clip @ stage.depth_to_stage(depth) @ scale
        corners = np.array([(0, 0, 1), (1, 0, 1), (0, 1, 1), (1, 1, 1)], np.float64) @ m.T
        if np.all(corners[:, 2] < 0):
            m = -m  # the same homography, with w > 0 so nothing is clipped away
        self.prog["to_clip"].write(mat3_bytes(m))
        for unit, (name, texture) in enumerate(textures.items()):
            texture.use(unit)
            if self.prog.get(name, None) is not None:  # the driver drops unused samplers
                self.prog[name] = unit
        self.vao.render(moderngl.TRIANGLE_STRIP)


SPRITE_VERTEX = """
#version 330
uniform mat3 to_clip;
in vec2 corner;       // -1..1
in vec2 center;       // output pixels
in float radius;      // output pixels
in vec4 rgba;         // straight colour and alpha
out vec2 local;
out vec4 tint;
void main() {
    local = corner;
    tint = rgba;
    vec3 p = to_clip * vec3(center + corner * radius, 1.0);
    gl_Position = vec4(p.xy, 0.0, p.z);
}
"""
SPRITE_FRAGMENT = """
#version 330
uniform float softness;   // 0: hard disc, 1: all glow
in vec2 local;
in vec4 tint;
out vec4 color;
void main() {
    float r = length(local);
    float a = tint.a * (1.0 - smoothstep(1.0 - softness, 1.0, r));
    color = vec4(tint.rgb * a, a);
}
"""


class Sprites:
    """Round soft sprites, one instanced draw for all of them."""

    def __init__(self, ctx: moderngl.Context, softness: float = 0.5, capacity: int = 256) -> None:
        self.ctx = ctx
        self.prog = ctx.program(vertex_shader=SPRITE_VERTEX, fragment_shader=SPRITE_FRAGMENT)
        self.prog["softness"] = softness
        self.corners = ctx.buffer(np.array([(-1, -1), (1, -1), (-1, 1), (1, 1)], "f4").tobytes())
        self.capacity = 0
        self._grow(capacity)

    def _grow(self, capacity: int) -> None:
        if self.capacity:
            self.vao.release()
            self.instances.release()
        self.capacity = capacity
        self.instances = self.ctx.buffer(reserve=capacity * 7 * 4, dynamic=True)
        self.vao = self.ctx.vertex_array(self.prog, [(self.corners, "2f", "corner"),
                                                     (self.instances, "2f 1f 4f/i", "center", "radius", "rgba")])

    def draw(self, target, centers, radii, rgba) -> None:
        """centers (N, 2) px, radii (N,) px, rgba (N, 4) straight colour in 0..1."""
        n = len(radii)
        if n == 0:
            return
        if n > self.capacity:
            self._grow(max(n, 2 * self.capacity))
        data = np.empty((n, 7), "f4")
        data[:, 0:2], data[:, 2], data[:, 3:7] = centers, radii, rgba
        self.instances.write(data.tobytes())
        self.prog["to_clip"].write(mat3_bytes(target.to_clip))
        self.vao.render(moderngl.TRIANGLE_STRIP, instances=n)

    def release(self) -> None:
        for obj in (self.vao, self.instances, self.corners, self.prog):
            obj.release()


class Particles:
    """Points with a velocity and a lifetime, stepped with numpy (no per-particle Python)."""

    def __init__(self, capacity: int) -> None:
        self.capacity = capacity
        self.pos = np.zeros((0, 2))
        self.vel = np.zeros((0, 2))
        self.age = np.zeros(0)
        self.life = np.zeros(0)
        self.size = np.zeros(0)
        self.rgb = np.zeros((0, 3))

    def spawn(self, pos, vel, life, size, rgb) -> None:
        n = len(vel)
        self.pos = np.r_[self.pos, np.broadcast_to(pos, (n, 2))][-self.capacity:]
        self.vel = np.r_[self.vel, vel][-self.capacity:]
        self.age = np.r_[self.age, np.zeros(n)][-self.capacity:]
        self.life = np.r_[self.life, np.broadcast_to(life, (n,))][-self.capacity:]
        self.size = np.r_[self.size, np.broadcast_to(size, (n,))][-self.capacity:]
        self.rgb = np.r_[self.rgb, np.broadcast_to(rgb, (n, 3))][-self.capacity:]

    def step(self, dt: float, drag: float = 0.0, gravity: float = 0.0) -> None:
        """Advances `dt` seconds; drag per second (0..1), gravity in px/s^2 (down)."""
        self.age += dt
        alive = self.age < self.life
        for name in ("pos", "vel", "age", "life", "size", "rgb"):
            setattr(self, name, getattr(self, name)[alive])
        self.vel *= (1.0 - drag) ** dt
        self.vel[:, 1] += gravity * dt
        self.pos += self.vel * dt

    def draw(self, sprites: Sprites, target) -> None:
        fade = 1.0 - self.age / self.life
        rgba = np.c_[self.rgb, fade]
        sprites.draw(target, self.pos, self.size * (0.4 + 0.6 * fade), rgba)

    def __len__(self) -> int:
        return len(self.age)


STAGE_VERTEX = """
#version 330
uniform mat3 issv_to_clip;
uniform vec2 issv_size;  // output pixels
in vec2 in_uv;           // 0..1 over the stage, v down
out vec2 {uv};           // texture coordinate, t = 1 at the top
void main() {{
    {uv} = vec2(in_uv.x, 1.0 - in_uv.y);
    vec3 p = issv_to_clip * vec3(in_uv * issv_size, 1.0);
    gl_Position = vec4(p.xy, 0.0, p.z);
}}
"""


class StageQuad(UnitQuad):
    """A fragment shader over the whole stage, through the target's `to_clip` (so keystoned):
    its `uv` input (or `uv_name`) runs 0..1 with t = 1 at the stage's top."""

    def __init__(self, ctx: moderngl.Context, fragment_shader: str, uv_name: str = "uv") -> None:
        super().__init__(ctx, STAGE_VERTEX.format(uv=uv_name), fragment_shader)

    def draw(self, target) -> None:
        self.prog["issv_to_clip"].write(mat3_bytes(target.to_clip))
        self.prog["issv_size"].value = tuple(float(v) for v in target.size)
        self.vao.render(moderngl.TRIANGLE_STRIP)


COPY_FRAGMENT = """
#version 330
uniform sampler2D image;
in vec2 uv;
out vec4 color;
void main() { color = texture(image, uv); }
"""


class Offscreen:
    """A smaller texture to draw an expensive full-stage shader into, then stretched onto the
    effect's target in one cheap pass: `begin()`, draw it as onto a target (`size`, `to_clip`),
    `target.use()`, `draw(target)`."""

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int], scale: float) -> None:
        self.ctx = ctx
        self.size = size  # what the shader drawn into it sees as the output size
        self.to_clip = plain_clip(size)
        resolution = (max(1, round(size[0] * scale)), max(1, round(size[1] * scale)))
        self.texture = ctx.texture(resolution, 4)
        self.texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
        self.texture.repeat_x = self.texture.repeat_y = False
        self.fbo = ctx.framebuffer([self.texture])
        self.quad = StageQuad(ctx, COPY_FRAGMENT)

    def begin(self) -> None:
        """Binds and clears the texture, blending off: draw the shader next."""
        self.fbo.use()
        self.ctx.enable_only(moderngl.NOTHING)
        self.fbo.clear(0.0, 0.0, 0.0, 0.0)

    def draw(self, target) -> None:
        self.texture.use(0)
        self.quad.draw(target)

    def release(self) -> None:
        for obj in (self.quad, self.fbo, self.texture):
            obj.release()
