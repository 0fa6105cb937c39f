"""Presenting depth from any sensor as another sensor would see it (e.g. a Kinect v1).

A pinhole camera resampled to other intrinsics from the same viewpoint sees the same rays: each
output pixel takes the reading of the input pixel on its ray (nearest neighbour, so no depth is
invented between surfaces; outside the input's field of view there is no reading). World
positions do not change; only the image and its intrinsics do.
"""
from __future__ import annotations

import cv2
import numpy as np

from host import DepthFrame, Intrinsics

#: Kinect v1 (and SimpleOpenNI's default mode): 640x480, 57 x 43 degrees.
KINECT_V1: tuple[tuple[int, int], Intrinsics] = ((640, 480), Intrinsics.from_fov(640, 480, 57.0, 43.0))


def to_geometry(depth: DepthFrame, size: tuple[int, int], intrinsics: Intrinsics) -> DepthFrame:
    """The same frame seen with `intrinsics` at `size` (width, height); unchanged if already so."""
    if (depth.width, depth.height) == size and depth.intrinsics == intrinsics:
        return depth
    src = depth.intrinsics
    sx, sy = src.fx / intrinsics.fx, src.fy / intrinsics.fy
    # output pixel (u', v') -> input pixel on the same ray
    m = np.array([[sx, 0.0, src.cx - intrinsics.cx * sx],
                  [0.0, sy, src.cy - intrinsics.cy * sy]])
    data = cv2.warpAffine(depth.data, m, size, flags=cv2.INTER_NEAREST | cv2.WARP_INVERSE_MAP,
                          borderMode=cv2.BORDER_CONSTANT, borderValue=0)
    return DepthFrame(data, intrinsics, depth.frame_id, depth.timestamp, depth.capture_time,
                      depth.mirrored, depth.truth)
