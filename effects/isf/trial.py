"""One headless GL context on which ISF files are tried one after the other (`issv isf`)."""
from __future__ import annotations

from pathlib import Path
from typing import Any

import cv2
import moderngl
import numpy as np

from effects.depth_view import DepthView
from effects.isf.header import IMAGE_TYPES, IsfError
from effects.isf.passes import IsfRenderer, Output
from effects.isf.shader import IsfShader
from effects.isf.sound import SoundTextures
from host import Frame, Stage
from host.app import EffectCanvas, headless_context, plugin_class
from host.audio import ToneSound

FPS = 30.0
DEMO_SECONDS = 2.0  # the synthetic performer has raised a hand by then


def colour_spread(pixels: np.ndarray) -> float:
    """The pixels' standard deviation as colours (0..1): how far they lie from their mean colour,
    0 exactly when the frame is one colour, however saturated (a solid red frame is flat)."""
    flat = pixels.reshape(-1, pixels.shape[-1]).astype(np.float64) / 255.0
    return float(np.sqrt(flat.var(axis=0).mean()))


class DemoViews:
    """The demo's depth view, gray and turbo, one frame per show frame (made once, reused)."""

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int]) -> None:
        self.ctx, self.size = ctx, size
        synthetic = plugin_class("sources", "synthetic")
        self.source = synthetic(synthetic.Options(width=320, height=240, seed=1))
        self.source.open()
        for _ in range(int(DEMO_SECONDS * FPS)):
            self.source.read()
        self.stage = Stage(size=size, fps=FPS, backend="synthetic", ctx=ctx)
        self.effects = {name: DepthView(DepthView.Options(colormap=name)) for name in ("gray", "turbo")}
        for effect in self.effects.values():
            effect.setup(self.stage)
        self.canvas = EffectCanvas(ctx, size)
        self.frames: list[dict[str, moderngl.Texture]] = []
        self.fbos: list[moderngl.Framebuffer] = []

    def at(self, index: int) -> dict[str, moderngl.Texture]:
        while len(self.frames) <= index:
            self.frames.append(self._render(len(self.frames)))
        return self.frames[index]

    def _render(self, index: int) -> dict[str, moderngl.Texture]:
        depth = self.source.read()
        frame = Frame(index + 1, depth.capture_time, depth)
        out = {}
        for name, effect in self.effects.items():
            texture = self.ctx.texture(self.size, 4)
            texture.repeat_x = texture.repeat_y = False
            fbo = self.ctx.framebuffer([texture])
            fbo.clear(0.0, 0.0, 0.0, 1.0)
            self.canvas.render(effect, frame, fbo)
            self.fbos.append(fbo)
            out[name] = texture
        return out

    def release(self) -> None:
        for fbo in self.fbos:
            fbo.release()
        for views in self.frames:
            for texture in views.values():
                texture.release()
        for effect in self.effects.values():
            effect.close()
        self.canvas.release()
        self.source.close()


class Trial:
    def __init__(self, size: tuple[int, int]) -> None:
        self.size = size
        self.ctx = headless_context()
        self.views = DemoViews(self.ctx, size)
        self.target = self.ctx.texture(size, 4)
        self.fbo = self.ctx.framebuffer([self.target])
        self.clock = 0.0
        tone = ToneSound(clock=lambda: self.clock)
        self.sound = SoundTextures(self.ctx, lambda: tone)

    def run(self, path: Path, frames: int, snapshot: Path | None) -> dict[str, Any]:
        result: dict[str, Any] = {"file": str(path), "ok": False, "error": None, "passes": 0, "kind": "generator",
                                  "mean": 0.0, "std": 0.0}
        runner = None
        try:
            shader = IsfShader(path)
            result["passes"], result["kind"] = len(shader.header.passes), shader.kind
            runner = IsfRenderer(self.ctx, shader)
            for i in range(frames):
                self._frame(runner, shader, i)
            pixels = np.frombuffer(self.fbo.read(components=3), np.uint8).reshape(self.size[1], self.size[0], 3)
            error = self.ctx.error
            if error != "GL_NO_ERROR":
                raise IsfError(f"{path}: OpenGL reports {error} while rendering")
            result.update(ok=True, mean=round(float(pixels.mean()) / 255, 4), std=round(colour_spread(pixels), 4))
            if snapshot is not None:
                cv2.imwrite(str(snapshot), cv2.cvtColor(pixels[::-1], cv2.COLOR_RGB2BGR))
        except IsfError as error:
            result["error"] = str(error)
        except Exception as error:  # a driver error at draw time: the file fails, the others run
            result["error"] = f"{path}: {type(error).__name__}: {error}"
        finally:
            if runner is not None:
                runner.release()
        return result

    def _frame(self, runner: IsfRenderer, shader: IsfShader, index: int) -> None:
        self.clock = index / FPS
        views = self.views.at(index)
        images = {}
        for item in shader.header.inputs:
            if item.type == "image":
                images[item.name] = views["turbo" if item.name == "endImage" else "gray"]
            elif item.type in ("audio", "audioFFT"):
                images[item.name] = self.sound.texture(item.type, item.samples)

        def bind() -> None:
            self.fbo.use()
            self.ctx.enable_only(moderngl.BLEND)
            self.ctx.blend_func = moderngl.ONE, moderngl.ONE_MINUS_SRC_ALPHA

        self.fbo.clear(0.0, 0.0, 0.0, 1.0)  # as the stage: opaque black
        values = {i.name: i.default for i in shader.header.inputs if i.type not in IMAGE_TYPES}
        runner.draw(values, images, Output(bind, self.size), self.clock, 1.0 / FPS)

    def close(self) -> None:
        self.sound.release()
        self.views.release()
        self.fbo.release()
        self.target.release()
        self.ctx.release()
