"""`recording`: the depth images of an MCAP recording as a source, re-tracked by any backend.

Two backends fed the same recording see byte-identical depth: the comparison the thesis could not
make (ch. 6.2). Ground truth recorded with the depth (e.g. from the synthetic performer) comes along.
"""
from __future__ import annotations

import time
from pathlib import Path

from pydantic import BaseModel, ConfigDict, Field

from host import DepthFrame, Source
from host.errors import UserError
from host.options import ProfilePath
from host.recording import Recording, shifted_depth

FPS_PROBE_FRAMES = 10


class RecordingSourceOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    path: ProfilePath = Field(description="an MCAP recording made by `issv record`")
    loop: bool = False
    seek: float = Field(0.0, ge=0, description="start this many seconds into the recording")


class RecordingSource(Source):
    name = "recording"
    Options = RecordingSourceOptions

    @classmethod
    def for_recording(cls, path: Path, seek: float = 0.0) -> "RecordingSource":
        return cls(cls.Options(path=str(path), seek=seek))

    def open(self) -> None:
        o: RecordingSourceOptions = self.options
        self.recording = Recording(o.path)
        probe = []
        for depth in self.recording.depth_frames(o.seek):
            probe.append(depth)
            if len(probe) >= FPS_PROBE_FRAMES:
                break
        if not probe:
            raise UserError(f"{o.path}: the recording has no depth images after {o.seek} s to re-track")
        self.intrinsics = probe[0].intrinsics
        span = probe[-1].timestamp - probe[0].timestamp
        self.fps = (len(probe) - 1) / span if len(probe) > 1 and span > 0 else 30.0
        self._frames = self.recording.passes(depth_only=True, start=o.seek, loop=o.loop)

    def read(self) -> DepthFrame | None:
        item = next(self._frames, None)
        if item is None:
            return None
        depth, offset = item
        return shifted_depth(depth, offset, time.time())

    def close(self) -> None:
        if getattr(self, "recording", None) is not None:
            self.recording.close()
