"""The user's body frame: shoulder line, torso (spine) and head, from the segmented silhouette.

The torso is what remains of the user after a morphological opening wider than an arm but
narrower than a chest (arms vanish, the trunk stays); only the part near the body's own depth
plane counts, so a hand held in front of the chest does not drag the estimate. Constants are
anatomy in mm (shoulder-to-hip, crown-to-head-centre), the same for every performer.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import cv2
import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from backends.engine.anatomy import Anatomy, Stature
from backends.engine.quantiles import median, percentile
from backends.engine.segmentation import BEYOND_USER, Grid, Segment, bounding_box, height_above
from backends.engine.smoothing import OneEuroFilter, SmoothingOptions


_HOLE = np.ones((3, 3), np.uint8)
# Two feet side by side fill 150-290 mm of a silhouette's lowest row seen from the front (UTD-MHAD's
# four adults, 2.8 m away); a body cut off at the hips or thighs fills more.
FEET_MAX_WIDTH_MM = 300.0
WHOLE_PERSON_MM = 900.0  # no one standing is shorter (a 3-year-old: 950 mm): less is a body cut off


@cache
def _disc(k: int, transposed: bool = False) -> np.ndarray:
    """The k x k elliptic structuring element, or its transpose (a few sizes recur frame after frame)."""
    disc = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (k, k))
    return np.ascontiguousarray(disc.T) if transposed else disc


class BodyOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    core_width_mm: float = Field(220, gt=0, description="opening size: wider than an arm, narrower than a chest")
    outline_width_mm: float = Field(180, gt=0, description=(
        "opening size for the shoulder line: wider than an arm (80-120 mm), narrower than a chest seen "
        "side-on (220-280 mm), so a performer walking sideways keeps their shoulders"))
    plane_band_mm: float = Field(250, gt=0, description="points nearer than this in front of the torso are not trunk")
    shoulder_below_core_top_mm: float = Field(100, description="shoulder joints below the top of the trunk")
    spine_below_shoulder_mm: float = Field(240, description="spine joint below the shoulder line")
    trunk_height_mm: float = Field(550, gt=0, description="shoulder line to hips")
    joint_depth_mm: float = Field(110, ge=0, description="joints lie this far behind the body's front surface")
    head_radius_mm: float = Field(150, gt=0, description="half the width of the column the head is looked for in")
    head_width_mm: float = Field(120, gt=0, description=(
        "narrowest a head's top (crown_above_head_mm deep) is; a hand's is narrower"))
    shoulder_below_crown_mm: float = Field(350, gt=0, description="shoulder joints below the top of the head")
    crown_above_head_mm: float = Field(60, ge=0, description="top of the head (as the coarse grid sees it) above the head joint")
    hidden_crown_hold_s: float = Field(0.5, ge=0, description=(
        "while an arm in front hides the top of the head (a swipe past the face), the crown is taken "
        "where it was last seen, for up to this long, unless the user's top rises a head_radius_mm above it"))


@dataclass(frozen=True)
class Body:
    """A body frame in mm (camera coordinates): where hands are judged from."""

    torso: np.ndarray  # spine joint (x, y, z)
    head: np.ndarray
    shoulder_y: float
    hip_y: float  # below this, limbs are legs
    surface_z: float  # depth of the trunk's front surface
    face_z: float  # depth of the face: the head joint less a joint's depth
    user: UserBox  # the segment's user box it was estimated on, for the stages after it
    core: np.ndarray  # bool: the trunk's cells on that box (user.mask's shape)
    scale: float = 1.0  # the performer's anatomy relative to an adult's (anatomy.py)


@dataclass(frozen=True)
class UserBox:
    """One frame's user on their box of the grid, BEYOND_USER cells wider where the grid goes on
    (what hole filling, erosion and gap bridging look at), copied into contiguous arrays: the
    dozens of numpy operations each stage runs on them cost about half what they do on views of
    the whole grid's rows. The body frame, the hand detector and the skeleton share one."""

    box: tuple[slice, slice]
    grid: Grid
    mask: np.ndarray

    @classmethod
    def of(cls, seg: Segment) -> UserBox | None:
        """The segment's user box; None for an empty mask."""
        box = bounding_box(seg.mask, BEYOND_USER)
        if box is None:
            return None
        g = seg.grid.crop(box)
        z, x, y, area, mask = (np.ascontiguousarray(a) for a in (g.z, g.x, g.y, g.pixel_area_mm2, seg.mask[box]))
        return cls(box, Grid(z, x, y, area, g.cell_x, g.cell_y), mask)


class BodyEstimator:
    def __init__(self, options: BodyOptions, smoothing: SmoothingOptions) -> None:
        self.options = options
        self.smoothing = smoothing
        self.anatomy = Anatomy(options)
        self.stature = Stature()  # kept while the user is out of sight: they are as tall when back
        self.reset()

    def reset(self) -> None:
        self._surface_z: float | None = None
        self._last_crown: tuple[float, float] | None = None  # (t, mm): kept while an arm hides the head
        # The body moves slower than its outline flickers: the frame (spine x, shoulder line,
        # surface depth) and the head are smoothed before hands are judged from them.
        self._frame = OneEuroFilter(self.smoothing)
        self._head_filter = OneEuroFilter(self.smoothing)

    def estimate(self, seg: Segment, t: float) -> Body | None:
        """The body frame of this frame at `t` seconds (None without a user)."""
        scale = self.stature.scale  # as tall as the crowns seen so far: this frame's goes in for the next
        o = self.options = self.anatomy.at(scale)
        # All is done on the user's box (the same result as on the whole grid, faster): two empty
        # cells around the user where the grid goes on are all the openings need (the hole filling
        # reaches one cell beyond the user, the erosion needs one empty cell beyond to eat into the
        # user from that side, and an opening never grows past what it opens).
        user = UserBox.of(seg)
        if user is None:
            return None
        g, mask = user.grid, user.mask
        ref = self._surface_z if self._surface_z is not None else float(median(g.z[mask]))
        k = max(3, int(round(o.core_width_mm / (g.cell_x * ref))))
        k_outline = max(3, int(round(o.outline_width_mm / (g.cell_x * ref))))
        # The trunk's position and depth come from the part near its own plane (an arm held in
        # front would drag them); the shoulder line from the lower of two estimates that an arm
        # can only push up: the top of the outline without its thin parts (an arm across the
        # chest stays inside it), and the crown of the head less the head and neck.
        plane = mask & (g.z > ref - o.plane_band_mm)
        core = opened = self._open(plane, k)
        if np.count_nonzero(core) < 4:
            core = plane if plane.any() else mask
        outline = self._open(mask, k_outline)
        if np.count_nonzero(outline) < 4:
            outline = core
        centre_x = float(median(g.x[core]))
        shoulder_y = float(percentile(g.y[outline], 98)) - o.shoulder_below_core_top_mm
        head_x = self._leaning_head_x(g.x, g.y, mask, centre_x)
        spine_strip = mask & (np.abs(g.x - head_x) < o.head_radius_mm)
        column = spine_strip & (np.abs(g.z - ref) < o.plane_band_mm)
        crown = self._crown(g.y, column, spine_strip & (g.z <= ref - o.plane_band_mm), o.head_radius_mm)
        fresh = crown is not None  # this frame's crown, not one held while an arm hides it
        if crown is not None:
            self._last_crown = (t, crown)
        elif self._last_crown is not None and t - self._last_crown[0] <= o.hidden_crown_hold_s:
            # An arm in front hides the head without raising the user's top; a performer standing
            # up from a bend brings the head up in front of the body: no crown to hold then.
            top = self._top(g.y, spine_strip)
            crown = self._last_crown[1] if top is None or top <= self._last_crown[1] + o.head_radius_mm else None
        if crown is not None:
            shoulder_y = min(shoulder_y, crown - o.shoulder_below_crown_mm)
        trunk_rows = (g.y > shoulder_y - o.trunk_height_mm) & (g.y < shoulder_y)
        trunk = core & trunk_rows
        if not trunk.any():
            trunk = core
        # The spine's x from the trunk as the camera sees its outline, whatever lies in front of it
        # (each cell's ray at the trunk's depth): an arm across the chest hides part of the trunk
        # and would pull the middle of what is left away from the spine.
        before = mask & (g.z < ref + o.plane_band_mm)  # often the plane itself (nothing in front, nothing behind)
        seen = (opened if np.array_equal(before, plane) else self._open(before, k)) & trunk_rows | trunk
        tx = float(median(g.x[seen] / g.z[seen])) * ref
        tx, shoulder_y, surface = self._frame(t, np.array([tx, shoulder_y, median(g.z[trunk])])).tolist()
        self._surface_z = surface
        torso = np.array([tx, shoulder_y - o.spine_below_shoulder_mm, surface + o.joint_depth_mm])
        head_cells = column & (g.y > shoulder_y + 100)
        if crown is not None:  # a hand raised over the head is not its crown
            crown = min(crown, shoulder_y + o.shoulder_below_crown_mm)
            if fresh and seg.floor is not None:
                self.stature.add(height_above(seg.floor, tx, crown, surface))
            elif fresh and (height := _height_above_feet(seg, crown)) is not None:
                self.stature.add(height)
        if crown is None or not head_cells.any():
            head = np.array([tx, shoulder_y + o.shoulder_below_crown_mm - o.crown_above_head_mm, torso[2]])
        else:
            head = np.array([median(g.x[head_cells]), crown - o.crown_above_head_mm,
                             median(g.z[head_cells]) + o.joint_depth_mm])
        head = self._head_filter(t, head)
        return Body(torso, head, shoulder_y, shoulder_y - o.trunk_height_mm, surface,
                    float(head[2]) - o.joint_depth_mm, user, core, scale)

    def _leaning_head_x(self, x: np.ndarray, y: np.ndarray, mask: np.ndarray, centre_x: float) -> float:
        """Where across to look for the head: above the spine, unless the user's top is a head-wide
        crest straddling the edge of that column, a third to a half of it inside (a performer
        walking in bent forward: the head 200+ mm to the side would else leave its far side beside
        the head joint, taken for a raised hand); then above the crest. A hand raised beside the
        head is narrower than a head, or wider with it, or crowns the user mostly outside."""
        o = self.options
        top = self._top(y, mask)
        if top is None:
            return centre_x
        crest = mask & (y > top - o.crown_above_head_mm)
        xs = x[crest]
        inside = np.abs(xs - centre_x) < o.head_radius_mm
        if (not 1 / 3 <= np.count_nonzero(inside) / inside.size < 1 / 2
                or not o.head_width_mm <= xs.max() - xs.min() <= 2 * o.head_radius_mm):
            return centre_x
        return float(median(xs))

    @staticmethod
    def _top(y: np.ndarray, cells: np.ndarray) -> float | None:
        """Height (mm) of the highest row with two or more of the cells."""
        row = _first_row_held(cells)
        if row is None:
            return None
        return float(median(y[row][cells[row]]))

    @classmethod
    def _crown(cls, y: np.ndarray, column: np.ndarray, in_front: np.ndarray, hidden_mm: float) -> float | None:
        """The top of the head's column; None when something in front of the body (an arm swiping
        past the face) covers the column just above it (within `hidden_mm`): the head may go on
        behind it, so the crown would read too low. A hand held higher, clear of the head, hides
        nothing."""
        crown = cls._top(y, column)
        if crown is None or (in_front & (y >= crown) & (y <= crown + hidden_mm)).any():
            return None
        return crown

    @staticmethod
    def _open(mask: np.ndarray, k: int) -> np.ndarray:
        """The cells of `mask` (a user box's) that remain after removing everything thinner than a
        k-cell disc. One-cell holes (missing readings, the shadow a depth sensor casts beside an
        arm) are filled for the shape but left out of the result: they have no depth to take a
        median of. A standing body is taller than wide: OpenCV's filters run faster along long
        rows, so the picture and the disc are transposed then (the same result; cv2.transpose
        copies faster than numpy)."""
        cells = mask.view(np.uint8)
        tall = cells.shape[0] > cells.shape[1]
        if tall:
            cells = cv2.transpose(cells)
        filled = cv2.morphologyEx(cells, cv2.MORPH_CLOSE, _HOLE)
        opened = cv2.morphologyEx(filled, cv2.MORPH_OPEN, _disc(k, tall))
        if tall:
            opened = cv2.transpose(opened)
        return opened.view(bool) & mask


ROW_HELD = 2  # a row holding this many of a silhouette's cells is part of it (one cell is noise)


def _first_row_held(cells: np.ndarray) -> int | None:
    """The top row of `_rows_held` (None: no such row). The box's top row is most often it:
    counting the cells of a row or two costs less than counting every row's."""
    picture = cells.view(np.uint8)
    _, top, _, height = cv2.boundingRect(picture)
    for row in range(top, top + height):
        if cv2.countNonZero(picture[row]) >= ROW_HELD:
            return row
    return None


def _rows_held(cells: np.ndarray) -> np.ndarray:
    """The rows holding `ROW_HELD` or more of the cells, top to bottom: where a silhouette's top
    and bottom are looked for."""
    return np.flatnonzero(np.count_nonzero(cells, axis=1) >= ROW_HELD)


def _height_above_feet(seg: Segment, crown: float) -> float | None:
    """The crown's height (mm) above the user's feet when no floor is in view but the feet are (a
    recording with its background removed): the user's lowest cells lie clear of the picture's
    bottom, with no reading in the BEYOND_USER rows under them (all the user's box holds), fill no
    more than a pair of feet's width, and lie a whole person's height below the crown. None
    otherwise: legs cut off by the picture's end, hidden behind something nearer, missing (dark
    trousers a depth camera reads nothing from), or someone seated at a desk too near the camera to
    read: a body cut off there would be taken for a child's."""
    g, mask = seg.grid, seg.mask
    rows = _rows_held(mask)
    if rows.size == 0 or rows[-1] >= mask.shape[0] - BEYOND_USER:
        return None
    bottom, columns = rows[-1], np.flatnonzero(mask.any(axis=0))
    cells = mask[bottom]
    if (g.z[bottom + 1:bottom + 1 + BEYOND_USER, columns[0]:columns[-1] + 1].any()
            or np.count_nonzero(cells) * g.cell_x * float(median(g.z[bottom][cells])) > FEET_MAX_WIDTH_MM):
        return None
    height = crown - float(median(g.y[bottom][cells]))
    return height if height >= WHOLE_PERSON_MM else None
