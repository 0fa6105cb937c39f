"""The show's sound, for effects: the newest samples, their level and their spectrum.

An audio input is put on `stage.extra["audio"]` (by the `audio` effect, first in the profile);
effects read it in `render`/`on_frame`: `sound.level()` (RMS, 0..1), `sound.spectrum(bins)`
(magnitudes, 0..1), `sound.window(n)` (the newest n samples per channel, -1..1). Three kinds:

- `FileSound`: a WAV/FLAC file (`soundfile`, the `issv[audio]` extra), its position set from the
  source's timestamps so that the picture and the sound stay in sync (seek, not a clock).
  `Playback` plays it aloud on an output device (`sounddevice`), following that position.
- `CaptureSound`: the default capture device through PortAudio (`sounddevice`, same extra). The
  device callback only overwrites a ring buffer (no queue, never blocking the audio thread).
- `ToneSound`: a test tone (`issv isf` feeds it to audio inputs).
"""
from __future__ import annotations

import threading
import time
from pathlib import Path

import numpy as np

from host.errors import UserError

AUDIO_EXTRA = "pip install 'issv[audio]'"


def portaudio(purpose: str):
    """The sounddevice module, or one error saying how to get it (it or the PortAudio library)."""
    try:
        import sounddevice
    except (ImportError, OSError) as error:  # OSError: the PortAudio library itself is missing
        raise UserError(f"audio: {purpose} needs sounddevice and PortAudio ({error}): {AUDIO_EXTRA}, "
                        "apt-get install libportaudio2") from None
    return sounddevice


def no_device(kind: str, device: str | int | None, error: Exception) -> UserError:
    return UserError(f"audio: no {kind} device {device if device is not None else '(default)'} ({error})")


def start_stream(kind: str, stream_class, device: str | int | None, channels: int, rate: int, callback):
    """A started PortAudio stream of float32 frames, or one error naming the missing device."""
    try:
        stream = stream_class(device=device, channels=channels, samplerate=rate, dtype="float32", callback=callback)
        stream.start()
    except Exception as error:  # PortAudioError, ValueError: no such device
        raise no_device(kind, device, error) from None
    return stream


class Sound:
    """Samples by time; subclasses give `window(n)`, the newest n frames as (n, channels) float32."""

    rate: int = 44100
    channels: int = 1

    def window(self, n: int) -> np.ndarray:
        raise NotImplementedError

    def level(self, n: int = 1024) -> float:
        """Root-mean-square of the newest n samples, all channels: 0 silence, ~0.7 a full-scale sine."""
        w = self.window(n)
        return float(np.sqrt(np.mean(np.square(w)))) if w.size else 0.0

    def spectrum(self, bins: int = 256) -> np.ndarray:
        """Magnitudes of `bins` frequency bands from 0 to rate/2 (Hann window, mono), about 0..1."""
        w = self.window(2 * bins).mean(axis=1)
        if not w.size:
            return np.zeros(bins, np.float32)
        mags = np.abs(np.fft.rfft(w * np.hanning(len(w))))[:bins] / (len(w) / 4)
        return np.clip(mags, 0.0, 1.0).astype(np.float32)

    def close(self) -> None:
        pass


class ToneSound(Sound):
    """A 440 Hz tone with two overtones, pulsing twice a second: audio shaders have something to show."""

    def __init__(self, clock=time.perf_counter) -> None:
        self.clock = clock

    def window(self, n: int) -> np.ndarray:
        t = self.clock() - np.arange(n)[::-1] / self.rate
        pulse = 0.6 + 0.4 * np.sin(2 * np.pi * 2 * t)
        tone = sum(a * np.sin(2 * np.pi * f * t) for f, a in ((440, 0.5), (880, 0.25), (1320, 0.125)))
        return (pulse * tone).astype(np.float32)[:, None]


class FileSound(Sound):
    """A sound file read whole; `seek(seconds)` sets where the newest sample is."""

    def __init__(self, path: Path) -> None:
        try:
            import soundfile
        except ImportError:
            raise UserError(f"audio: reading {path} needs soundfile: {AUDIO_EXTRA}") from None
        try:
            data, self.rate = soundfile.read(str(path), dtype="float32", always_2d=True)
        except (RuntimeError, OSError) as error:  # soundfile raises LibsndfileError (a RuntimeError)
            raise UserError(f"audio: cannot read {path}: {error} (WAV, FLAC or OGG)") from None
        self.data, self.channels = data, data.shape[1]
        self.position = 0

    @property
    def duration(self) -> float:
        return len(self.data) / self.rate

    def seek(self, seconds: float) -> None:
        self.position = int(min(max(seconds, 0.0), self.duration) * self.rate)

    def window(self, n: int) -> np.ndarray:
        start = self.position - n
        out = np.zeros((n, self.channels), np.float32)
        part = self.data[max(0, start):self.position]
        if len(part):
            out[n - len(part):] = part
        return out


class Playback:
    """A FileSound played aloud on the default (or a named) output device, in step with its position.

    The device pulls audio at its own pace; the file's position moves with the source's frames.
    The play head runs on by itself and jumps to the position when the two are more than
    `RESYNC_S` apart (the source looped, skipped or stalled), so the sound follows the picture
    without a click on every frame. Needs a sound card: not tested here (no device in CI).
    """

    RESYNC_S = 0.15

    def __init__(self, sound: FileSound, device: str | int | None = None) -> None:
        sounddevice = portaudio("playing")
        self.sound, self.head = sound, sound.position
        self.stream = start_stream("playback", sounddevice.OutputStream, device, sound.channels, sound.rate,
                                   self._callback)

    def _callback(self, outdata, frames, time_info, status) -> None:
        target = self.sound.position
        if abs(self.head - target) > self.RESYNC_S * self.sound.rate:
            self.head = target
        chunk = self.sound.data[self.head:self.head + frames]
        outdata[:len(chunk)] = chunk
        outdata[len(chunk):] = 0.0
        self.head += frames

    def close(self) -> None:
        self.stream.stop()
        self.stream.close()


class CaptureSound(Sound):
    """The default (or a named) capture device. Needs a sound card: cannot be tested here (no
    device in CI); the ring buffer logic is the same as FileSound's window."""

    def __init__(self, device: str | int | None = None, seconds: float = 1.0) -> None:
        sounddevice = portaudio("capture")
        try:
            info = sounddevice.query_devices(device, "input")
        except Exception as error:  # PortAudioError, ValueError: no such device
            raise no_device("capture", device, error) from None
        self.rate, self.channels = int(info["default_samplerate"]), max(1, min(2, int(info["max_input_channels"])))
        self.ring = np.zeros((int(self.rate * seconds), self.channels), np.float32)
        self.written = 0
        self.lock = threading.Lock()
        self.stream = start_stream("capture", sounddevice.InputStream, device, self.channels, self.rate, self._callback)

    def _callback(self, indata, frames, time_info, status) -> None:
        data = indata[-len(self.ring):]
        with self.lock:
            self.ring[(self.written + np.arange(len(data))) % len(self.ring)] = data
            self.written += len(data)

    def window(self, n: int) -> np.ndarray:
        size = len(self.ring)
        n = min(n, size)
        with self.lock:
            idx = (self.written - n + np.arange(n)) % size
            return self.ring[idx].copy()

    def close(self) -> None:
        self.stream.stop()
        self.stream.close()
