"""`audio`: the show's sound, for the effects after it: a sound file (WAV/FLAC) followed in step
with the source's timestamps, or a capture device (PortAudio). It draws nothing; it puts the
sound on `stage.extra["audio"]` (see host/audio.py), where `isf` feeds audio/audioFFT inputs and
`audio.level` bindings and Python effects read `level()` and `spectrum()`.

Without the extra, the file or a device, one message says why and the show goes on silent.
"""
from __future__ import annotations

import sys

from pydantic import BaseModel, ConfigDict, Field, model_validator

from host import Effect, Frame, Stage
from host.audio import AUDIO_EXTRA, CaptureSound, FileSound
from host.errors import UserError
from host.options import ProfilePath


class AudioOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    file: ProfilePath | None = Field(None, description="a WAV/FLAC file, in step with the source's time")
    device: str | int | None = Field(None, description="a capture device name or index (default: the "
                                     "system's default input), when there is no `file`")

    @model_validator(mode="after")
    def _one(self) -> "AudioOptions":
        if self.file is not None and self.device is not None:
            raise ValueError("give `file` (a sound file) or `device` (a capture device), not both")
        return self


class Audio(Effect):
    name = "audio"
    Options = AudioOptions

    @classmethod
    def availability(cls) -> str | None:
        import importlib.util
        if importlib.util.find_spec("soundfile") or importlib.util.find_spec("sounddevice"):
            return None  # one of the two is enough for its kind of input; setup names a missing one
        return f"needs soundfile (files) or sounddevice (capture): {AUDIO_EXTRA}"

    def setup(self, stage: Stage) -> None:
        super().setup(stage)
        self.sound = None
        self.start: float | None = None
        try:
            self.sound = FileSound(self.options.file) if self.options.file else CaptureSound(self.options.device)
        except UserError as error:
            sys.stderr.write(f"issv: {error}; the show goes on silent\n")
            return
        stage.extra["audio"] = self.sound

    def on_frame(self, frame: Frame) -> None:
        if isinstance(self.sound, FileSound) and frame.depth is not None:
            if self.start is None or frame.timestamp < self.start:  # first frame, or the source looped
                self.start = frame.timestamp
            self.sound.seek(frame.timestamp - self.start)

    def close(self) -> None:
        if self.sound is not None:
            self.sound.close()
            self.stage.extra.pop("audio", None)
