"""`replay`: a recording played back exactly as it was tracked: the same hands and gestures at
the same source timestamps, in real time or as fast as possible, looped, from any point.

Rehearse a show without the camera: effects cannot tell a replay from the live backend.
"""
from __future__ import annotations

import time
from pathlib import Path

from pydantic import BaseModel, ConfigDict, Field

from host import Backend, Frame, Gesture, Vec3
from host.options import ProfilePath
from host.recording import Recording, shifted_frame


class ReplayOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    path: ProfilePath = Field(description="an MCAP recording made by `issv record`")
    realtime: bool = Field(True, description="pace frames by their timestamps; false: as fast as possible")
    loop: bool = Field(False, description="start again at the end (time keeps running forwards)")
    seek: float = Field(0.0, ge=0, description="start this many seconds into the recording")


class ReplayBackend(Backend):
    name = "replay"
    Options = ReplayOptions
    needs_source = False

    @classmethod
    def for_recording(cls, path: Path) -> "ReplayBackend":
        """The recording's own tracks, as they were recorded, as fast as possible."""
        return cls(None, cls.Options(path=str(path), realtime=False))

    def init(self) -> None:
        o: ReplayOptions = self.options
        self.recording = Recording(o.path)
        self._frames = self.recording.passes(start=o.seek, loop=o.loop)
        self._origin: tuple[float, float] | None = None  # (wall clock, source time) of the first frame
        self._last: Frame | None = None

    def update(self) -> Frame | None:
        item = next(self._frames, None)
        if item is None:
            return None
        frame, offset = item
        if self.options.realtime:
            self._pace(frame.timestamp + offset)
        self._last = shifted_frame(frame, offset, time.time())
        return self._last

    def finish(self) -> tuple[Gesture, ...]:
        """The gestures the end of the recorded source completed, as they were recorded."""
        return self.recording.end_gestures

    def _pace(self, t: float) -> None:
        """Sleep until source time `t` is due, counted from the first frame played."""
        if self._origin is None:
            self._origin = (time.perf_counter(), t)
        delay = self._origin[0] + (t - self._origin[1]) - time.perf_counter()
        if delay > 0:
            time.sleep(delay)

    def stop(self) -> None:
        super().stop()
        if getattr(self, "recording", None) is not None:
            self.recording.close()

    def world_to_depth(self, position: Vec3) -> tuple[float, float, float]:
        """Projects into the recorded depth images (the camera the show was tracked with)."""
        if self._last is None or self._last.depth is None:
            return super().world_to_depth(position)
        return self._last.depth.world_to_depth(position)
