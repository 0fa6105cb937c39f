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
        self._depth: moderngl.Texture | None = None
        self._mask: moderngl.Texture | None = None
        self._labels: moderngl.Texture | None = None
        self._depth_seq = self._mask_seq = self._labels_seq = -1

    def _texture(self, old: moderngl.Texture | None, size: tuple[int, int], dtype: str) -> moderngl.Texture:
        if old is not None and old.size == size and old.dtype == dtype:
            return old
        if old is not None:
            old.release()
        tex = self.ctx.texture(size, 1, dtype=dtype)
        tex.filter = (moderngl.NEAREST, moderngl.NEAREST)
        tex.repeat_x = tex.repeat_y = False
        return tex

    def depth(self) -> moderngl.Texture | None:
        frame = self.frame
        if frame is None or frame.depth is None:
            return None
        if frame.seq != self._depth_seq:
            d = frame.depth
            self._depth = self._texture(self._depth, (d.width, d.height), "f4")
            # Row 0 of the image is its top: store it at the texture's top (GL's t = 1).
            self._depth.write(np.ascontiguousarray(d.data[::-1], dtype=np.float32) * np.float32(0.001))
            self._depth_seq = frame.seq
        return self._depth

    def mask(self) -> moderngl.Texture | None:
        frame = self.frame
        if frame is None or frame.user_mask is None:
            return None
        if frame.seq != self._mask_seq:
            m = frame.user_mask
            self._mask = self._texture(self._mask, (m.shape[1], m.shape[0]), "f1")
            self._mask.write(np.ascontiguousarray(m[::-1], dtype=np.uint8) * np.uint8(255))
            self._mask_seq = frame.seq
        return self._mask

    def labels(self) -> moderngl.Texture | None:
        frame = self.frame
        if frame is None or frame.user_labels is None:
            return None
        if frame.seq != self._labels_seq:
            labels = frame.user_labels
            self._labels = self._texture(self._labels, (labels.shape[1], labels.shape[0]), "f1")
            self._labels.write(np.ascontiguousarray(labels[::-1], dtype=np.uint8))
            self._labels_seq = frame.seq
        return self._labels

    def release(self) -> None:
        for tex in (self._depth, self._mask, self._labels):
            if tex is not None:
                tex.release()
