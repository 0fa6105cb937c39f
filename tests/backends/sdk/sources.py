"""Small in-process sources for the adapter tests (not fakes of anything: plain test sources)."""
from __future__ import annotations

import numpy as np
from pydantic import BaseModel, ConfigDict

from host import DepthFrame, Intrinsics, Source


def wall_frames(n: int = 12, size: tuple[int, int] = (160, 120)) -> list[DepthFrame]:
    """A wall at 3 m with a box moving across it, at 30 Hz."""
    w, h = size
    intrinsics = Intrinsics.from_fov(w, h, 58.0, 45.0)
    out = []
    for i in range(n):
        data = np.full((h, w), 3000, np.uint16)
        data[h // 3: h // 2, 5 + 4 * i: 25 + 4 * i] = 2000
        out.append(DepthFrame(data, intrinsics, frame_id=i, timestamp=i / 30.0))
    return out


class Camera(Source):
    """A live source (as a camera is): what Nuitrack could open itself."""

    name = "camera"
    live = True

    def __init__(self, scene: list[DepthFrame] | None = None) -> None:
        super().__init__()
        self.scene = scene if scene is not None else wall_frames()
        self.intrinsics = self.scene[0].intrinsics
        self.opened = 0

    def open(self) -> None:
        self.opened += 1
        self._i = 0

    def read(self) -> DepthFrame | None:
        if self._i >= len(self.scene):
            return None
        self._i += 1
        return self.scene[self._i - 1]


class RecordingOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    path: str = "performance.npz"
    loop: bool = False


class Recording(Camera):
    """A recorded source (it has a path): no middleware can open it as its sensor."""

    name = "clip"
    live = False
    Options = RecordingOptions


class Oni(Camera):
    """Stands for the `oni` source: once open it holds an OpenNI2 device (the fake's) for NiTE2 and
    `frames`, the file's frame count; read() plays `scene` (for the open engine)."""

    name = "oni"
    Options = RecordingOptions

    def __init__(self, uri: bytes, frames: int) -> None:
        super().__init__()
        self.options = RecordingOptions(path=uri.decode())
        self.uri, self.frames, self.closed = uri, frames, 0

    def open(self) -> None:
        from openni import openni2

        super().open()
        self.device = openni2.Device.open_file(self.uri)
        self.mirrored = False

    def close(self) -> None:
        self.device.close()
        self.closed += 1
