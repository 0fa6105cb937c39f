"""The operator's overlay: backend, its input and rate, sFPS, rFPS, effective FPS, latency, the last gestures,
the source's own figures, each layer's GPU time.

Text is drawn with OpenCV into a small RGBA image and uploaded at most 4 times a second, so the
HUD costs one small blended quad per frame.
"""
from __future__ import annotations

import time

import cv2
import moderngl
import numpy as np

from host.metrics import Metrics

FONT = cv2.FONT_HERSHEY_SIMPLEX
REFRESH_S = 0.25
ROWS = 7  # the lines below
VERTEX = """
#version 330
in vec2 in_pos;
in vec2 in_uv;
out vec2 uv;
void main() { uv = in_uv; gl_Position = vec4(in_pos, 0.0, 1.0); }
"""
FRAGMENT = """
#version 330
uniform sampler2D text;
in vec2 uv;
out vec4 color;
void main() { color = texture(text, uv); }
"""


def lines(m: Metrics, layers: str = "") -> list[str]:
    sfps, rfps = m.live()
    lat = m.latency(recent=120)
    last = ", ".join(g.name for g in list(m.last_gestures)[-3:]) or "-"
    return [f"backend {m.backend}", f"input {m.input_label}",
            f"sFPS {sfps:5.1f}  rFPS {rfps:5.1f}  eff {(sfps + rfps) / 2:5.1f}",
            f"latency p50 {lat['p50']:5.1f} ms  p99 {lat['p99']:5.1f} ms",
            f"gestures {last}",
            m.source_line(), layers]


class Hud:
    """A text panel in the output's top-left corner, scaled with the output height."""

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int]) -> None:
        self.ctx = ctx
        self.scale = max(0.4, size[1] / 1080)
        self.line_h = int(34 * self.scale)
        # wide enough for an input label like `webcam file take.mp4 640x480, 27 fps, pose 24 ms`
        self.panel = (min(size[0] - 16, int(1100 * self.scale)), self.line_h * ROWS + int(14 * self.scale))
        pw, ph = self.panel
        self.texture = ctx.texture(self.panel, 4)
        x0, y1 = -1.0 + 2 * 8 / size[0], 1.0 - 2 * 8 / size[1]
        x1, y0 = x0 + 2 * pw / size[0], y1 - 2 * ph / size[1]
        quad = np.array([(x0, y0, 0, 0), (x1, y0, 1, 0), (x0, y1, 0, 1), (x1, y1, 1, 1)], "f4")
        self.prog = ctx.program(vertex_shader=VERTEX, fragment_shader=FRAGMENT)
        self.vbo = ctx.buffer(quad.tobytes())
        self.vao = ctx.vertex_array(self.prog, [(self.vbo, "2f 2f", "in_pos", "in_uv")])
        self._next = 0.0

    def _update(self, m: Metrics, layers: str) -> None:
        pw, ph = self.panel
        img = np.zeros((ph, pw, 4), np.uint8)
        img[..., 3] = 150  # a dark translucent panel (premultiplied: black stays black)
        for i, text in enumerate(lines(m, layers)):
            font, thick, margin = 0.9 * self.scale, max(1, int(2 * self.scale)), int(10 * self.scale)
            width = cv2.getTextSize(text, FONT, font, thick)[0][0]
            font *= min(1.0, (pw - 2 * margin) / max(width, 1))  # a long line is made smaller, never cut
            cv2.putText(img, text, (margin, self.line_h * (i + 1)), FONT, font, (255, 255, 255, 255), thick,
                        cv2.LINE_AA)
        self.texture.write(np.ascontiguousarray(img[::-1]))

    def draw(self, m: Metrics, target: moderngl.Framebuffer, layers: str = "") -> None:
        """`layers`: one line of each layer's GPU time (host/render/gputime.py)."""
        now = time.monotonic()
        if now >= self._next:
            self._next = now + REFRESH_S
            self._update(m, layers)
        target.use()
        self.ctx.enable(moderngl.BLEND)
        self.ctx.blend_func = moderngl.ONE, moderngl.ONE_MINUS_SRC_ALPHA
        self.texture.use(0)
        self.vao.render(moderngl.TRIANGLE_STRIP)
        self.ctx.disable(moderngl.BLEND)

    def release(self) -> None:
        for obj in (self.vao, self.vbo, self.prog, self.texture):
            obj.release()
