"""`audio`: the show's sound, for the effects after it: a sound file (WAV/FLAC) followed in step
with the source's timestamps and played aloud (`play`, on the default output device), or a capture
device (PortAudio). It draws nothing; it puts the sound on `stage.extra["audio"]` (see
host/audio.py), where `isf` feeds audio/audioFFT inputs and `audio.level` bindings and Python
effects read `level()` and `spectrum()`.

Without the extra, the file or a device, one message says why and the show goes on silent. A file
with no output device to play it on still drives the effects; one message says it is not heard.
"""
from __future__ import annotations

import sys

from pydantic import BaseModel, ConfigDict, Field, model_validator

from host import Effect, Frame, Stage
from host.audio import AUDIO_EXTRA, CaptureSound, FileSound, Playback
from host.errors import UserError
from host.options import ProfilePath


class AudioOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    file: ProfilePath | None = Field(None, description="a WAV/FLAC file, in step with the source's time")
    device: str | int | None = Field(None, description="a capture device name or index (default: the "
                                     "system's default input), when there is no `file`")
    play: bool = Field(True, description="play the `file` aloud on the default output device, in step "
                       "with the source (false: only the effects hear it)")

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
        self.sound = self.playback = None
        self.start: float | None = None
        try:
            self.sound = FileSound(self.options.file) if self.options.file else CaptureSound(self.options.device)
        except UserError as error:
            sys.stderr.write(f"issv: {error}; the show goes on silent\n")
            return
        stage.extra["audio"] = self.sound
        if self.options.file and self.options.play:
            try:
                self.playback = Playback(self.sound)
            except UserError as error:
                sys.stderr.write(f"issv: {error}; {self.options.file} drives the effects but is not heard\n")

    def on_frame(self, frame: Frame) -> None:
        if isinstance(self.sound, FileSound) and frame.depth is not None:
            if self.start is None or frame.timestamp < self.start:  # first frame, or the source looped
                self.start = frame.timestamp
            self.sound.seek(frame.timestamp - self.start)

    def close(self) -> None:
        if self.playback is not None:
            self.playback.close()
        if self.sound is not None:
            self.sound.close()
            self.stage.extra.pop("audio", None)
