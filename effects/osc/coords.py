"""The coordinate spaces positions are sent in: millimetres, normalised 0..1, or stage pixels."""
from __future__ import annotations

from typing import Literal

import numpy as np

from host import DepthFrame, Intrinsics, Stage, Vec3

Space = Literal["mm", "normalized", "stage"]


class Projector:
    """Converts camera millimetres (x right, y up, z away) into the chosen space.

    - `mm`: unchanged.
    - `normalized`: x, y = the point's place in the depth image as fractions (0 left/top, 1
      right/bottom); z = (z - near) / (far - near) over `depth_range` millimetres.
    - `stage`: x, y = output pixels from the top-left, through the profile's camera-to-stage
      calibration (without one, the depth image stretched over the output); z in millimetres.
    """

    def __init__(self, space: Space, stage: Stage, depth_range: tuple[float, float]) -> None:
        self.space = space
        self.stage = stage
        self.near, self.far = depth_range
        self.depth: DepthFrame | None = None

    @property
    def ready(self) -> bool:
        """Whether positions can be converted: mm always; the others need a depth image's geometry."""
        return self.space == "mm" or self.depth is not None

    def see(self, depth: DepthFrame | None) -> None:
        """Remember the newest depth image: its intrinsics and size define the projection."""
        if depth is not None:
            self.depth = depth

    def assume_kinect(self) -> None:
        """No depth image came with the frames (e.g. a remote backend sent none): project as the
        reference sensor of docs/architecture.md, a Kinect v1 (640x480, 57 x 43 degrees)."""
        w, h = 640, 480
        self.depth = DepthFrame(np.zeros((h, w), np.uint16), Intrinsics.from_fov(w, h, 57, 43))

    def __call__(self, position: Vec3) -> Vec3:
        if self.space == "mm":
            return position
        x, y, z = position
        safe = (x, y, max(z, 1.0))  # a point at or behind the camera has no projection
        if self.space == "stage":
            sx, sy = self.stage.to_stage(safe, self.depth)
            return (sx, sy, z)
        u, v, _ = self.depth.world_to_depth(safe)
        return (u / self.depth.width, v / self.depth.height, (z - self.near) / (self.far - self.near))
