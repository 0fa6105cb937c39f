"""Sensor images as textures, uploaded at most once per sensor frame however many effects use them.

Render frames outnumber sensor frames (60 vs 30 Hz) and several effects read the same depth:
uploading on demand and keying on the frame's `seq` keeps llvmpipe's memory traffic minimal.
"""
from __future__ import annotations

import moderngl
import numpy as np

from host.model import Frame


class FrameTextures:
    """The newest frame's depth (R32F, metres, 0 = no reading), user mask (R8, 1 = performer)
    and user labels (R8 holding the label: a shader reads round(r * 255), 0 = nobody, else the
    user id)."""

    def __init__(self, ctx: moderngl.Context) -> None:
        self.ctx = ctx
        self.frame: Frame | None = None
        self._textures: dict[str, moderngl.Texture] = {}
        self._seqs: dict[str, int] = {}  # which frame each texture holds

    def _texture(self, old: moderngl.Texture | None, size: tuple[int, int], dtype: str) -> moderngl.Texture:
        if old is not None and old.size == size and old.dtype == dtype:
            return old
        if old is not None:
            old.release()
        tex = self.ctx.texture(size, 1, dtype=dtype)
        tex.filter = (moderngl.NEAREST, moderngl.NEAREST)
        tex.repeat_x = tex.repeat_y = False
        return tex

    def _image(self, name: str, image: np.ndarray | None, dtype: str, scale: float | None) -> moderngl.Texture | None:
        """Texture `name` holding `image` * `scale` of the newest frame, written once per frame."""
        if image is None:
            return None
        if self._seqs.get(name) != self.frame.seq:
            pixels = np.ascontiguousarray(image[::-1], dtype=np.float32 if dtype == "f4" else np.uint8)
            tex = self._textures[name] = self._texture(self._textures.get(name), (image.shape[1], image.shape[0]), dtype)
            # Row 0 of the image is its top: store it at the texture's top (GL's t = 1).
            tex.write(pixels if scale is None else pixels * pixels.dtype.type(scale))
            self._seqs[name] = self.frame.seq
        return self._textures[name]

    def depth(self) -> moderngl.Texture | None:
        if self.frame is None or self.frame.depth is None:
            return None
        return self._image("depth", self.frame.depth.data, "f4", 0.001)

    def mask(self) -> moderngl.Texture | None:
        return None if self.frame is None else self._image("mask", self.frame.user_mask, "f1", 255)

    def labels(self) -> moderngl.Texture | None:
        return None if self.frame is None else self._image("labels", self.frame.user_labels, "f1", None)

    def release(self) -> None:
        for tex in self._textures.values():
            tex.release()
        self._textures.clear()
        self._seqs.clear()
