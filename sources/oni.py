"""`oni`: OpenNI2 recordings (.oni files) played through the OpenNI2 runtime.

Uses Debian's `libopenni2-0` (or any OpenNI2 redistributable) through the PyPI `openni`
bindings (module `openni.openni2`), found by host.devices (shared with the NiTE2 backend).

The OpenNI2 file player paces frames itself (`speed` 1.0 = as recorded), like a camera: the source
is `live`, and a backend slower than the file sees the newest frame, as it would live. With
`realtime = false` the player runs in OpenNI2's manual mode instead: each read decodes the next
frame, none is skipped, as fast as the show reads (tests, benchmarks, offline analysis).
"""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from host import DepthFrame, Intrinsics, Source
from host.devices import INSTALL, LIB, bindings_dir, find_runtime
from host.errors import UserError
from host.options import ProfilePath

DEFAULT_FOV_DEG = (58.0, 45.0)  # PrimeSense / Kinect-class depth camera, when the file does not say
STALL_S = 2.0  # no frame for this long: the file cannot be played
CLOSE_SETTLE_S = 0.05  # after stopping the stream, for the player thread to stop walking it
MANUAL = -1.0  # OpenNI2's playback speed for "one frame per read" (PlayerDevice.cpp: XN_PLAYBACK_SPEED_MANUAL)


class OniOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    path: ProfilePath = Field(description="an OpenNI2 recording (.oni)")
    loop: bool = False
    speed: float = Field(1.0, gt=0, le=10, description="OpenNI2 playback speed: 1.0 = as recorded")
    realtime: bool = Field(True, description="at the recorded pace times `speed` (false: every frame, as fast "
                                             "as the show reads; `speed` is then unused)")


class OniSource(Source):
    name = "oni"
    Options = OniOptions
    live = True  # OpenNI2's player paces the file

    @classmethod
    def availability(cls) -> str | None:
        try:
            import openni.openni2  # noqa: F401
        except ImportError:
            return "the PyPI package `openni` (OpenNI2 bindings) is missing: pip install openni"
        library = find_runtime()
        if library is None:
            return f"the OpenNI2 runtime ({LIB}) is not installed: {INSTALL}"
        drivers = library.parent / "OpenNI2" / "Drivers"
        if not any(drivers.glob("libOniFile.so*")):
            return f"OpenNI2's file driver (libOniFile.so) is missing in {drivers}: {INSTALL}"
        return None

    def open(self) -> None:
        reason = self.availability()
        if reason is not None:
            raise UserError(f"source 'oni': {reason}")
        from openni import openni2
        from openni.utils import OpenNIError

        self._openni2, self._error = openni2, OpenNIError
        path = Path(self.options.path)
        if not path.is_file():
            raise UserError(f"{path}: no such .oni file")
        try:
            openni2.initialize(str(bindings_dir(find_runtime())))
            self.device = openni2.Device.open_file(str(path).encode())
            self.stream = self.device.create_depth_stream()
        except (OpenNIError, openni2.InitializationError) as error:
            raise UserError(f"{path}: OpenNI2 cannot open it as a recording with depth: {error}") from None
        if self.stream is None:
            raise UserError(f"{path}: the recording has no depth stream")
        mode = self.stream.get_video_mode()
        self._scale = self._mm_scale(mode.pixelFormat)
        self.width, self.height = mode.resolutionX, mode.resolutionY
        self.fps = float(mode.fps or 30)
        fov = (self._try(self.stream.get_horizontal_fov, None), self._try(self.stream.get_vertical_fov, None))
        fov_deg = tuple(np.degrees(fov)) if None not in fov else DEFAULT_FOV_DEG  # not every recording has it
        self.intrinsics = Intrinsics.from_fov(self.width, self.height, *fov_deg)
        self.mirrored = bool(self._try(self.stream.get_mirroring_enabled, True))
        self.frames = int(self._try(lambda: self.device.playback.get_number_of_frames(self.stream), -1))
        self.device.playback.set_speed(self.options.speed if self.options.realtime else MANUAL)
        self.device.playback.set_repeat_enabled(self.options.loop)
        self.stream.start()
        self._first_us: int | None = None
        self._last_index = -1

    def _try(self, get, default):
        try:
            return get()
        except self._error:
            return default

    def _mm_scale(self, fmt) -> float:
        formats = {self._openni2.PIXEL_FORMAT_DEPTH_1_MM: 1.0, self._openni2.PIXEL_FORMAT_DEPTH_100_UM: 0.1}
        if fmt not in formats:
            raise UserError(f"{self.options.path}: depth pixel format {fmt} is not millimetres or 100 um; "
                            f"re-record with a depth stream in DEPTH_1_MM")
        return formats[fmt]

    def read(self) -> DepthFrame | None:
        if not self.options.loop and 0 < self.frames <= self._last_index:
            return None
        if self._openni2.wait_for_any_stream([self.stream], STALL_S) is None:
            if self._last_index >= 0 and not self.options.loop and self._last_index >= self.frames - 2:
                return None  # the player stopped at the end of the file
            raise UserError(f"{self.options.path}: OpenNI2 delivered no depth frame for {STALL_S:.0f} s "
                            f"(after frame {self._last_index}); the file is damaged or its depth cannot be decoded")
        frame = self._openni2.VideoStream.read_frame(self.stream)
        raw = np.frombuffer(frame.get_buffer_as_uint16(), dtype=np.uint16)
        pixels = raw.reshape(frame.height, frame.stride // 2)[:, : frame.width].copy()
        if self._scale != 1.0:
            pixels = np.round(pixels * self._scale).astype(np.uint16)
        self._first_us = frame.timestamp if self._first_us is None else self._first_us
        self._last_index = frame.frameIndex
        return DepthFrame(pixels, self.intrinsics, frame_id=frame.frameIndex,
                          timestamp=(frame.timestamp - self._first_us) / 1e6, mirrored=self.mirrored)

    def close(self) -> None:
        stream = getattr(self, "stream", None)
        if stream is not None:
            # OpenNI2's player thread walks its stream list unlocked, busily while a stream is started
            # (PlayerDevice::MainLoop); closing a started stream edited that list under it and
            # segfaulted about once in 10-30 closes here. Stopped, the thread idles in 10 ms sleeps.
            self._try(stream.stop, None)
            time.sleep(CLOSE_SETTLE_S)
        for thing in ("stream", "device"):
            handle = getattr(self, thing, None)
            if handle is not None:
                self._try(handle.close, None)
