"""ISF's audio inputs as textures: `audio` is the waveform (width = samples, one row per
channel, 0.5 = silence, 0..1), `audioFFT` the spectrum (width = bins, magnitudes 0..1). The
samples come from the show's sound (`stage.extra["audio"]`, see host/audio.py); without one the
textures are silent (a flat 0.5 waveform, an empty spectrum)."""
from __future__ import annotations

from typing import Callable

import moderngl
import numpy as np

from host.audio import Sound

DEFAULT_SAMPLES = 512


class SoundTextures:
    """`source()` gives the sound now (the `audio` effect may come later in the profile)."""

    def __init__(self, ctx: moderngl.Context, source: Callable[[], Sound | None]) -> None:
        self.ctx, self.source = ctx, source
        self.textures: dict[tuple[str, int], moderngl.Texture] = {}

    @property
    def sound(self) -> Sound | None:
        return self.source()

    def level(self) -> float:
        return self.sound.level() if self.sound is not None else 0.0

    def texture(self, kind: str, samples: int) -> moderngl.Texture:
        """This render's waveform or spectrum; `samples` 0 means the ISF default (512)."""
        n = samples or DEFAULT_SAMPLES
        if self.sound is None:
            rows = np.full((1, n), 0.5 if kind == "audio" else 0.0, np.float32)
        elif kind == "audio":
            rows = np.clip(self.sound.window(n).T * 0.5 + 0.5, 0.0, 1.0)
        else:
            rows = self.sound.spectrum(n)[None, :]
        key = (kind, n)
        texture = self.textures.get(key)
        if texture is None or texture.size != (n, rows.shape[0]):
            if texture is not None:
                texture.release()
            texture = self.textures[key] = self.ctx.texture((n, rows.shape[0]), 4, dtype="f4")
            texture.repeat_x = texture.repeat_y = False
        texture.write(np.repeat(rows[..., None], 4, axis=2).astype(np.float32).tobytes())
        return texture

    def release(self) -> None:
        for texture in self.textures.values():
            texture.release()
