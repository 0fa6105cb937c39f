"""The user's body frame: shoulder line, torso (spine) and head, from the segmented silhouette.

The torso is what remains of the user after a morphological opening wider than an arm but
narrower than a chest (arms vanish, the trunk stays); only the part near the body's own depth
plane counts, so a hand held in front of the chest does not drag the estimate. Constants are
anatomy in mm (shoulder-to-hip, crown-to-head-centre), the same for every performer.
"""
from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from backends.engine.segmentation import Segment


class BodyOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    core_width_mm: float = Field(220, gt=0, description="opening size: wider than an arm, narrower than a chest")
    plane_band_mm: float = Field(250, gt=0, description="points nearer than this in front of the torso are not trunk")
    shoulder_below_core_top_mm: float = Field(40, description="shoulder joints below the top of the trunk")
    spine_below_shoulder_mm: float = Field(300, description="spine joint below the shoulder line")
    trunk_height_mm: float = Field(550, gt=0, description="shoulder line to hips")
    joint_depth_mm: float = Field(110, ge=0, description="joints lie this far behind the body's front surface")
    head_radius_mm: float = Field(150, gt=0)
    crown_above_head_mm: float = Field(60, ge=0, description="top of the head (as the coarse grid sees it) above the head joint")


@dataclass(frozen=True)
class Body:
    """A body frame in mm (camera coordinates): where hands are judged from."""

    torso: np.ndarray  # spine joint (x, y, z)
    head: np.ndarray
    shoulder_y: float
    hip_y: float  # below this, limbs are legs
    surface_z: float  # depth of the trunk's front surface
    core: np.ndarray  # (h, w) bool: trunk cells on the grid


class BodyEstimator:
    def __init__(self, options: BodyOptions) -> None:
        self.options = options
        self._surface_z: float | None = None

    def reset(self) -> None:
        self._surface_z = None

    def estimate(self, seg: Segment) -> Body | None:
        o, g, mask = self.options, seg.grid, seg.mask
        z_user = g.z[mask]
        if z_user.size == 0:
            return None
        ref = self._surface_z if self._surface_z is not None else float(np.median(z_user))
        k = max(3, int(round(o.core_width_mm / (g.cell_x * ref))))
        kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (k, k))
        # The outline gives the shoulder line (an arm across the chest stays inside it); the trunk's
        # position and depth come from the part near its own plane (an arm in front would drag them).
        outline = self._open(mask, kernel)
        plane = mask & (g.z > ref - o.plane_band_mm)
        core = self._open(plane, kernel)
        if core.sum() < 4:
            core = plane if plane.any() else mask
        if outline.sum() < 4:
            outline = core
        top = float(np.percentile(g.y[outline], 98))
        shoulder_y = top - o.shoulder_below_core_top_mm
        trunk = core & (g.y > shoulder_y - o.trunk_height_mm)
        if not trunk.any():
            trunk = core
        tx = float(np.median(g.x[trunk]))
        surface = float(np.median(g.z[trunk]))
        self._surface_z = surface
        torso = np.array([tx, shoulder_y - o.spine_below_shoulder_mm, surface + o.joint_depth_mm])
        head = self._head(seg, tx, shoulder_y, surface, torso)
        return Body(torso, head, shoulder_y, shoulder_y - o.trunk_height_mm, surface, core)

    @staticmethod
    def _open(mask: np.ndarray, kernel: np.ndarray) -> np.ndarray:
        """What remains of `mask` after removing everything thinner than the kernel."""
        return cv2.morphologyEx(mask.view(np.uint8), cv2.MORPH_OPEN, kernel).view(bool) & mask

    def _head(self, seg: Segment, tx: float, shoulder_y: float, surface: float, torso: np.ndarray) -> np.ndarray:
        o, g = self.options, seg.grid
        near = (seg.mask & (g.y > shoulder_y + 50) & (g.y < shoulder_y + 500)
                & (np.abs(g.x - tx) < o.head_radius_mm) & (np.abs(g.z - surface) < 300))
        if near.sum() < 3:
            return np.array([tx, shoulder_y + 250.0, torso[2]])
        crown = float(np.percentile(g.y[near], 95))
        return np.array([float(np.median(g.x[near])), crown - o.crown_above_head_mm,
                         float(np.median(g.z[near])) + o.joint_depth_mm])
