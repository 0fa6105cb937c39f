"""User segmentation from one depth image: no learned background, so it works from the first frame.

On a coarse grid (about 160 columns whatever the sensor's resolution) the depth becomes world
millimetres; a floor plane found by RANSAC among near-horizontal planes below the camera, with
nothing under it, is removed; depth jumps cut the image into surfaces; every person-sized surface
(judged in mm and m^2, not pixels) between `min_distance_mm` and `max_distance_mm` (0.5 to 4.5 m)
that stands on something (nobody floats over a tall gap without readings) is a person (up to
`max_people`, nearest first; someone so close that the picture's bottom cuts them off when a head
sits on shoulders), and each
small surface within arm's reach in front of a person (a forearm pointed at the camera is cut off
from the body by its own depth edge) joins the nearest such person. Clips whose background is
already removed are simply the easy case: no floor is found and the user is the only surface.
An arm across the body cuts it in two along its depth edges: surfaces that were one person a frame
ago stay one. Who is who from frame to frame is people.py's job; the segmenter only finds them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import cv2
import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from backends.engine.quantiles import median, percentiles
from host import DepthFrame

ONE_CELL_GAP = cv2.getStructuringElement(cv2.MORPH_CROSS, (3, 3))  # closing with it bridges a missing cell
RING = np.ones((5, 5), np.uint8)  # two cells around a surface: past the cut band at its edge
# Someone cut off by the picture's bottom (segmentation.Segmenter._head_and_shoulders), in mm:
HEAD_MM = 150  # the top this deep is the head (crown to chin: 5-year-old ~190, adult ~230)
SHOULDERS_MM = 400  # the shoulders are within this of the crown (0.18 x height: 190 child, 340 tall adult)
SHOULDERS_TO_HEAD = 1.5  # shoulders are at least this many heads wide (a 5-year-old 1.8, an adult 2.6)
ABOVE_CROWN_MM = 300  # looked at straight above the crown ...
BEHIND_MM = 150  # ... for a surface less than this behind it (an own head cut off is ~100 mm behind the chest)
BEYOND_USER = 2  # cells around a user its body frame and hand detector look at (hole filling, erosion, gap bridging)
FLOOR_UNDER = 0.01  # share of the lower cells under a floor found or kept: more, and it is no floor
SHADOW_MM = 75  # a depth camera's shadow beside a nearer surface is at most its baseline wide there (Kinect: 75 mm)
MAX_COVERED = 0.25  # share of the crown's columns with such a surface above: more, and it is no crown
BODY_DEPTH_MM = 250  # a body's thickness: the pieces of one lie within it of each other, someone behind lies further


class SegmentationOptions(BaseModel):
    """Physical limits of what counts as a person (mm, m^2) and of the sensor's useful range."""

    model_config = ConfigDict(extra="forbid")
    grid_width: int = Field(160, ge=40, description="columns of the internal grid (positions stay full-resolution mm)")
    near_mm: float = Field(300, ge=0, description="readings nearer than this are noise")
    far_mm: float = Field(8000, gt=0, description="readings farther than this are ignored")
    edge_mm: float = Field(60, gt=0, description="a depth jump larger than edge_mm + edge_ratio * z separates surfaces")
    edge_ratio: float = Field(0.03, ge=0)
    floor: bool = Field(True, description="look for a floor plane and remove it")
    floor_tolerance_mm: float = Field(60, gt=0, description="points this close to the floor plane are floor")
    floor_max_tilt_deg: float = Field(40, gt=0, lt=90, description="how far the floor normal may lean from the camera's up")
    floor_min_span_mm: float = Field(1000, gt=0, description="a floor is at least this wide (a seated lap is not)")
    min_camera_height_mm: float = Field(300, ge=0, description=(
        "the camera is at least this high above the floor: a plane through the camera is seen edge on, "
        "so any band of the picture fits it (a wall and a child's legs, when no floor is in view)"))
    floor_every: int = Field(30, ge=1, description=(
        "a floor found is kept while it still fits (as many cells on it as when looking for one, "
        "next to none under it), for at most this many frames, then looked for afresh (while none "
        "is found, in every frame); 1 looks for it in every frame"))
    min_user_area_m2: float = Field(0.08, gt=0, description="frontal area of the smallest user (a head and shoulders)")
    min_user_height_mm: float = Field(450, gt=0)
    min_whole_user_height_mm: float = Field(900, gt=0, description=(
        "a surface this tall, cell to cell, may be a whole person whatever is under it (a squatting "
        "adult, a small child; a clip with its background removed); a shorter one must stand on "
        "something (max_gap_below_mm)"))
    max_gap_below_mm: float = Field(500, gt=0, description=(
        "a surface shorter than a whole person has, within this under its lowest cells, a reading "
        "(legs, the floor, what hides them), a nearer surface's shadow or the picture's end: "
        "nobody floats over a taller gap without readings (a shelf over a dark cabinet)"))
    min_cut_user_height_mm: float = Field(250, gt=0, description=(
        "a surface going on below the picture (someone close to the camera) spans at least this in "
        "height, cell to cell, not the box at its mean depth: a 5-year-old's crown to shoulders"))
    max_head_width_mm: float = Field(200, gt=0, description=(
        "its top 150 mm (the head) is no wider than a head (at most 165 mm, with hair); a table top or a chair back is wider"))
    min_shoulder_width_mm: float = Field(250, gt=0, description=(
        "150-400 mm below its top it is this wide (a 5-year-old's shoulders) and 1.5 times its head"))
    max_user_width_mm: float = Field(2300, gt=0, description="arms spread; a wall is wider")
    max_user_depth_spread_mm: float = Field(600, gt=0, description="std of depth over the user; a side wall is deeper")
    reach_mm: float = Field(1000, gt=0, description="a detached surface this close in front of the user is part of them")
    rim_depth_mm: float = Field(700, gt=0, description="cut cells next to the user within this depth of them are theirs")
    min_part_area_m2: float = Field(0.002, gt=0, description="smaller detached surfaces are noise")
    max_part_area_m2: float = Field(0.3, gt=0, description="larger ones are no arm (a wall, the floor)")
    max_enclosed: float = Field(0.5, ge=0, le=1, description=(
        "a surface whose surroundings are more than this share nearer surfaces is background seen "
        "between them (a piece of wall between a raised arm and the head), not a person"))
    max_people: int = Field(4, ge=1, le=15, description="at most this many people, the nearest")
    min_distance_mm: float = Field(500, ge=0, description=(
        "a person's mean depth is at least this (a Kinect sees people from 0.8 m; a near-range "
        "camera such as an SR305 sees someone at 0.7 m)"))
    max_distance_mm: float = Field(4500, gt=0, description="and at most this (farther, the depth is too coarse)")


@dataclass(frozen=True)
class Grid:
    """The coarse grid of one frame: depth and world coordinates in mm (0 where no reading)."""

    z: np.ndarray  # (h, w) float32 mm, 0 = no reading
    x: np.ndarray
    y: np.ndarray
    pixel_area_mm2: np.ndarray  # frontal area one grid cell covers at its depth
    cell_x: float  # width of a grid cell in mm per mm of depth (step / fx)
    cell_y: float  # height of a grid cell in mm per mm of depth (step / fy)

    @property
    def shape(self) -> tuple[int, int]:
        return self.z.shape  # type: ignore[return-value]

    def crop(self, box: tuple[slice, slice]) -> "Grid":
        """The grid's cells in `box` (views, no copies)."""
        return Grid(self.z[box], self.x[box], self.y[box], self.pixel_area_mm2[box], self.cell_x, self.cell_y)


def bounding_box(mask: np.ndarray, margin: int = 0) -> tuple[slice, slice] | None:
    """The rows and columns holding `mask`'s cells, `margin` cells wider on each side (within the
    array); None for an empty mask."""
    x, y, w, h = cv2.boundingRect(mask.view(np.uint8))
    if w == 0:
        return None
    return slice(max(0, y - margin), y + h + margin), slice(max(0, x - margin), x + w + margin)


@dataclass(frozen=True)
class Segment:
    """One person found in one frame."""

    mask: np.ndarray  # (h, w) bool on the grid
    grid: Grid
    floor: np.ndarray | None = None  # the floor plane in view (nx, ny, nz, d): n.p + d = height above it

    def crop(self, box: tuple[slice, slice]) -> "Segment":
        """The segment's cells in `box`, on the same floor."""
        return replace(self, mask=self.mask[box], grid=self.grid.crop(box))


@dataclass(frozen=True, eq=False)
class Person:
    """One person's segment with what identifies them across frames (mm, camera coordinates)."""

    segment: Segment
    centre: np.ndarray  # (x, y, z): mean of the person's main surface
    top_mm: float  # height of the highest cell (the crown, or a raised hand)
    cells: int  # how many grid cells the person covers


class Segmenter:
    """Finds the people in each frame; remembers only the floor plane and where the people were last
    frame (`segment()` stays on the first; a person cut in two stays one)."""

    def __init__(self, options: SegmentationOptions) -> None:
        self.options = options
        self._rays: dict[tuple, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}
        self._floor: np.ndarray | None = None  # (nx, ny, nz, d): n.p + d = height above the floor
        self._plane: np.ndarray | None = None  # the floor removed now (None: none found when last looked)
        self._floor_age = 0  # frames since `_plane` was found
        self._last_masks: list[np.ndarray] = []  # the people's surfaces last frame, the first `segment()`'s user
        self._last_z: np.ndarray | None = None  # the last frame's grid depth
        self._rng = np.random.default_rng(0)

    def grid(self, depth: DepthFrame) -> Grid:
        o = self.options
        step = max(1, round(depth.width / o.grid_width))
        cells = np.ascontiguousarray(depth.data[::step, ::step])
        readings = cv2.inRange(cells, math.ceil(o.near_mm), math.floor(o.far_mm)) != 0  # readings are whole mm
        z = cells.astype(np.float32) * readings
        gx, gy, cell = self._ray_grid(depth, step, z.shape)
        i = depth.intrinsics
        return Grid(z, z * gx, z * gy, (z * z) * cell, step / i.fx, step / i.fy)

    def _ray_grid(self, depth: DepthFrame, step: int, shape: tuple[int, int]):
        """Per grid cell: x/z and y/z of its ray, and its solid angle; cached per geometry."""
        key = (shape, step, depth.intrinsics)
        if key not in self._rays:
            v, u = np.mgrid[0:shape[0], 0:shape[1]].astype(np.float32) * step
            gx, gy, _ = depth.intrinsics.depth_to_world(u, v, 1.0)
            cell = np.float32(step * step / (depth.intrinsics.fx * depth.intrinsics.fy))
            self._rays[key] = (gx.astype(np.float32), gy.astype(np.float32), cell)
        return self._rays[key]

    def segment(self, depth: DepthFrame) -> Segment | None:
        """The one user: the nearest person, or the one seen last while they stay in view."""
        people = self.people(depth, stay=True)
        return people[0].segment if people else None

    def people(self, depth: DepthFrame, stay: bool = False) -> list[Person]:
        """Every person in view, nearest first (`stay`: the person seen first last time, first
        again while they are there). All share one grid: segmenting is done once per frame."""
        g = self.grid(depth)
        valid = g.z > 0
        if self.options.floor:
            valid &= ~self._floor_mask(g, valid)
        count, labels = self._surfaces(g, valid)
        found = self._pick_people(g, labels, count, stay)
        cut = valid & (labels == 0)
        out = []
        for mask, centre in found:
            mask = self._with_rim(g, mask, cut)
            cut &= ~mask  # a rim cell is one person's
            first = bounding_box(mask)[0].start
            top = float(np.max(g.y[first][mask[first]]))
            out.append(Person(Segment(mask, g, self._plane), centre, top, np.count_nonzero(mask)))
        self._last_masks, self._last_z = [mask for mask, _ in found], g.z  # their surfaces, not the rims
        return out

    # -- floor -------------------------------------------------------------------------------
    def _floor_mask(self, g: Grid, valid: np.ndarray) -> np.ndarray:
        """The cells on the floor. A floor that still fits is kept (for up to `floor_every`
        frames): the search is the dearest step of segmenting, and a camera mostly stands still."""
        o = self.options
        height = None if self._plane is None else height_above(self._plane, g.x, g.y, g.z)
        if height is None or self._floor_age >= o.floor_every or not self._fits(height, valid):
            self._plane, self._floor_age = self._find_floor(g, valid), 0
            if self._plane is None:
                return np.zeros_like(valid)
            self._floor = self._plane
            height = height_above(self._plane, g.x, g.y, g.z)
        self._floor_age += 1
        return valid & (height < o.floor_tolerance_mm + 0.01 * g.z)

    def _fits(self, height: np.ndarray, valid: np.ndarray) -> bool:
        """Whether the floor still lies where it was found: as many of the lower cells on it as
        a floor found needs, and (almost) none under it (else the camera moved, or it never was
        the floor)."""
        tolerance = self.options.floor_tolerance_mm
        third = valid.shape[0] // 3
        h, lower = height[third:], valid[third:]
        cells = np.count_nonzero(lower)
        on = np.count_nonzero(lower & (np.abs(h) < tolerance))
        under = np.count_nonzero(lower & (h < -tolerance))
        return cells >= 50 and on >= max(30, 0.1 * cells) and under <= FLOOR_UNDER * cells

    def _find_floor(self, g: Grid, valid: np.ndarray, samples: int = 600, hypotheses: int = 48) -> np.ndarray | None:
        """RANSAC among near-horizontal planes below the camera with most points above them; the
        last floor competes too. The best is the floor if it has (almost) nothing under it, as
        `_fits` asks of it later: a level plane across a wall has the rest of the wall under it."""
        o = self.options
        third = valid.shape[0] // 3  # the floor shows in the lower part of a level camera's view
        idx = np.flatnonzero(valid[third:]) + third * valid.shape[1]
        if idx.size < 50:
            return None
        idx = self._rng.choice(idx, size=min(samples, idx.size), replace=False)
        pts = np.stack([g.x.flat[idx], g.y.flat[idx], g.z.flat[idx]], axis=1).astype(np.float64)
        tri = pts[self._rng.integers(0, len(pts), size=(hypotheses, 3))]
        a = tri[:, 0]
        n = _cross(tri[:, 1] - a, tri[:, 2] - a)
        norm = np.sqrt(np.einsum("ij,ij->i", n, n))
        ok = norm > 1e-6
        n = n[ok] / norm[ok, None]
        n *= np.where(n[:, 1:2] < 0, -1.0, 1.0)  # normals point up
        d = -np.einsum("ij,ij->i", n, a[ok])
        planes = np.concatenate([n, d[:, None]], axis=1)
        if self._floor is not None:
            planes = np.vstack([planes, self._floor])
        planes = planes[(planes[:, 1] >= np.cos(np.radians(o.floor_max_tilt_deg)))
                        & (planes[:, 3] >= o.min_camera_height_mm)]
        if len(planes) == 0:
            return None
        heights = pts @ planes[:, :3].T + planes[:, 3]
        inliers = np.abs(heights) < o.floor_tolerance_mm
        below = heights < -o.floor_tolerance_mm
        score = inliers.sum(axis=0) - 4 * below.sum(axis=0)  # a floor has (almost) nothing under it
        best = int(np.argmax(score))
        support = pts[inliers[:, best]]
        if len(support) < max(30, 0.1 * len(pts)) or below[:, best].sum() > FLOOR_UNDER * len(pts):
            return None
        high, low = percentiles(support[:, 0], (95, 5))
        span = high - low
        return planes[best] if span >= o.floor_min_span_mm else None

    # -- surfaces and the user ---------------------------------------------------------------
    def _surfaces(self, g: Grid, valid: np.ndarray) -> tuple[int, np.ndarray]:
        """How many labels, and the label image of the connected surfaces: 4-neighbours whose depths
        differ by less than the edge threshold.

        Only the far side of a jump is cut, so the near surface (the user) keeps its outline. A cell
        without a reading between two with readings (a sensor's dropped reading, a row lost in
        rescaling) bridges them at the farther one's depth, so a line of holes does not cut a person
        in two; bridges join surfaces but are not part of them.
        """
        z = g.z * valid
        bridge = ~valid & cv2.morphologyEx(valid.view(np.uint8), cv2.MORPH_CLOSE, ONE_CELL_GAP).view(bool)
        np.copyto(z, cv2.dilate(z, ONE_CELL_GAP), where=bridge)
        valid = valid | bridge
        # A cell is cut when a neighbour is nearer by more than the threshold at the neighbour's
        # depth: z - n > edge + ratio * n, i.e. the nearest neighbour n < (z - edge) / (1 + ratio).
        # A cell without a reading is nobody's nearest: +inf. Those are now exactly the cells at
        # z = 0 (a bridge has its neighbour's depth), which one threshold finds faster than np.where.
        nowhere = cv2.threshold(z, 0, np.inf, cv2.THRESH_BINARY_INV)[1]  # +inf at z <= 0, else 0
        nearest = cv2.erode(nowhere + z, ONE_CELL_GAP)
        o = self.options
        keep = valid & (nearest >= (z - np.float32(o.edge_mm)) / np.float32(1 + o.edge_ratio))
        count, labels = cv2.connectedComponents(keep.view(np.uint8), connectivity=4)
        labels[bridge] = 0
        return count, labels

    def _with_rim(self, g: Grid, mask: np.ndarray, cut: np.ndarray) -> np.ndarray:
        """Give back the user's cells that were cut as the far side of a jump onto the user itself
        (the chest behind an arm held across it); the far background stays out."""
        box = bounding_box(mask, 1)  # the rim is one cell around the user
        own, z = mask[box], g.z[box]
        near = cv2.dilate(own.view(np.uint8), np.ones((3, 3), np.uint8)).view(bool)
        depth = float(median(z[own]))
        out = mask.copy()
        out[box] |= near & cut[box] & (np.abs(z - depth) < self.options.rim_depth_mm)
        return out

    def _enclosed(self, g: Grid, labels: np.ndarray, sized: np.ndarray, box: np.ndarray, k: int,
                  depth: float) -> float:
        """The share of the surface cells around surface `k` (two cells out, past the cut band at
        its edge) that belong to nearer person-sized surfaces: a person stands in front of what
        surrounds them (their own detached forearm aside)."""
        x, y, w, h = (int(v) for v in box[:4])
        y0, x0 = max(0, y - 2), max(0, x - 2)
        window = labels[y0:y + h + 2, x0:x + w + 2]
        mask = window == k
        ring = cv2.dilate(mask.view(np.uint8), RING).view(bool) & ~mask & (window > 0)
        around, z = window[ring], g.z[y0:y + h + 2, x0:x + w + 2][ring]
        nearer = sized[around] & (z < self._nearer_than(depth))
        return np.count_nonzero(nearer) / max(1, around.size)

    def _head_and_shoulders(self, g: Grid, labels: np.ndarray, box: np.ndarray, k: int) -> bool:
        """Whether surface `k`, cut off by the picture's bottom, is someone close to the camera:
        they show at least a head on shoulders, whatever their size or distance.

        Heights are the cells' own (camera y), so a floor or a table top seen at a slant, tall in
        the picture but not in the room, is no one. Widths are the cells' summed widths in a row
        (a gap, between a head and a hand beside it, is not counted). The top must be a crown:
        straight above it there is only the room behind the person, or nothing; a surface there (an
        arm held across the chest, or the person's own head cut off by missing readings) means
        this is a piece of a body, not its top.
        """
        o = self.options
        x, y, w, h = (int(v) for v in box[:4])
        box_ = np.s_[y:y + h, x:x + w]
        mask = labels[box_] == k
        ys, zs = g.y[box_], g.z[box_]
        heights = ys[mask]
        crown = float(heights.max())
        if crown - float(heights.min()) < o.min_cut_user_height_mm:
            return False
        top = mask & (ys >= crown - HEAD_MM)
        chest = mask & (ys < crown - HEAD_MM) & (ys >= crown - SHOULDERS_MM)
        head = float((zs * top).sum(axis=1).max()) * g.cell_x
        shoulders = float((zs * chest).sum(axis=1).max()) * g.cell_x
        if head > o.max_head_width_mm or shoulders < max(o.min_shoulder_width_mm, SHOULDERS_TO_HEAD * head):
            return False
        columns = np.flatnonzero(top.any(axis=0))
        first = y + np.argmax(top[:, columns], axis=0)  # the crown's row in each of its columns
        depth = float(zs[top].mean())
        cols = np.s_[:y + h, x + columns]
        z = g.z[cols] * (labels[cols] > 0)  # surfaces only (a cut band is no cover)
        over = ((np.arange(y + h)[:, None] < first) & (g.y[cols] < crown + ABOVE_CROWN_MM)
                & (z > 0) & (z < depth + BEHIND_MM))
        return float(over.any(axis=0).mean()) <= MAX_COVERED

    def _stands_on_something(self, g: Grid, labels: np.ndarray, box: np.ndarray, k: int, depth: float) -> bool:
        """Whether surface `k`, above the picture's bottom, is a person's whole height, or the
        sensor sees something under it: under most of its lowest cells (those within two rows of
        its bottom), within `max_gap_below_mm`, a reading (the person's legs, the floor, what
        hides them), the shadow a nearer surface casts beside itself (a cell without a reading
        within SHADOW_MM of a nearer reading in its row: the legs of someone behind a child near
        the camera), or the picture's end. A person does not float over a tall gap; furniture
        over a dark cabinet does (the real OpenNI take's shelf: 0.7 m tall over 1.1 m of nothing)."""
        o = self.options
        x, y, w, h = (int(v) for v in box[:4])
        mask = labels[y:y + h, x:x + w] == k
        if float(np.ptp(g.y[y:y + h, x:x + w][mask])) >= o.min_whole_user_height_mm:
            return True
        gap = math.ceil(o.max_gap_below_mm / (g.cell_y * depth))  # rows the gap may span
        reach = math.ceil(SHADOW_MM / (g.cell_x * o.min_distance_mm))  # columns a shadow may span
        nearer = self._nearer_than(depth)
        lowest = h - 1 - np.argmax(mask[::-1], axis=0)  # each column's lowest cell (row in the box)
        cols = np.flatnonzero(mask.any(axis=0) & (lowest >= lowest.max() - 2))
        seen = 0
        for c in x + cols:
            first = y + lowest[c - x] + 1
            rows = slice(first, first + gap)
            if first + gap > labels.shape[0] or (g.z[rows, c] > 0).any():
                seen += 1
                continue
            lo = max(0, c - reach)
            side = g.z[rows, lo:c + reach + 1]
            apart = np.abs(np.arange(lo, lo + side.shape[1]) - c) * g.cell_x * side  # mm at the reading's depth
            seen += bool(((side > 0) & (side < nearer) & (apart <= SHADOW_MM)).any())
        return seen >= 0.5 * cols.size

    def _pick_people(self, g: Grid, labels: np.ndarray, count: int,
                     stay: bool) -> list[tuple[np.ndarray, np.ndarray]]:
        """(mask, centre of the main surface) per person, nearest first."""
        o = self.options
        if count <= 1:
            return []
        n, sum_z, zz, sum_x, sum_y = _per_surface(labels.ravel(), count, g.z, g.z.astype(np.float64) ** 2, g.x, g.y)
        n = np.maximum(n, 1)  # cells per surface (with readings)
        mean_z = sum_z / n
        area = zz * (g.cell_x * g.cell_y)  # a cell covers its depth squared times its solid angle
        area[0] = 0
        spread = np.sqrt(np.maximum(zz / n - mean_z ** 2, 0))
        person = ((area >= o.min_user_area_m2 * 1e6) & (spread <= o.max_user_depth_spread_mm)
                  & (mean_z >= o.min_distance_mm) & (mean_z <= o.max_distance_mm))
        person[0] = False
        boxes = _boxes(labels, person)
        ext_w = boxes[:, 2] * g.cell_x * mean_z  # bounding box in mm at the mean depth
        ext_h = boxes[:, 3] * g.cell_y * mean_z
        person &= ext_w <= o.max_user_width_mm
        tall = ext_h >= o.min_user_height_mm
        top, bottom = boxes[:, 1], boxes[:, 1] + boxes[:, 3]
        for k in _indices(person & ~tall & (bottom >= labels.shape[0]) & (top > 0)):
            tall[k] = self._head_and_shoulders(g, labels, boxes[k], k)
        person &= tall
        for k in _indices(person & (bottom < labels.shape[0])):
            person[k] = self._stands_on_something(g, labels, boxes[k], k, mean_z[k])
        if not person.any():
            return []
        sized = person.copy()
        for k in _indices(sized):
            person[k] = self._enclosed(g, labels, sized, boxes[k], k, mean_z[k]) <= o.max_enclosed
        if not person.any():
            return []
        whose = self._whose(g, labels, count, n)
        whose[area < o.min_part_area_m2 * 1e6] = -1  # noise
        rank = mean_z.copy()
        if stay:
            rank -= 2000.0 * (whose == 0)  # stay on the same person while they are there
        rank[~person] = np.inf
        people, piece_of = self._whole(g, labels, np.argsort(rank)[:np.count_nonzero(person)], whose, mean_z)
        people = people[:o.max_people]
        piece_of[piece_of >= len(people)] = -1
        # Detached parts: within reach of a person and not behind them; each joins the nearest.
        part = (area >= o.min_part_area_m2 * 1e6) & (area <= o.max_part_area_m2 * 1e6) & ~person
        part[0] = False
        centres = np.stack([sum_x / n, sum_y / n, mean_z], axis=1)
        offsets = centres[:, None, :] - centres[None, people, :]  # (surface, person, xyz)
        distance = np.linalg.norm(offsets, axis=2)
        within = (distance <= o.reach_mm) & (offsets[:, :, 2] < 150)
        part &= within.any(axis=1)
        owner = np.full(count, -1)
        owner[part] = np.argmin(np.where(within, distance, np.inf), axis=1)[part]
        owner[people] = np.arange(len(people))
        owner[piece_of >= 0] = piece_of[piece_of >= 0]
        return [(_labelled(labels, _indices(owner == k)), centres[p]) for k, p in enumerate(people)]

    def _whose(self, g: Grid, labels: np.ndarray, count: int, n: np.ndarray) -> np.ndarray:
        """For each surface, the person of the last frame (their index) over 30 % of its cells were,
        at the same depth (the depth changed less than a depth edge since: the same surface, not the
        wall seen where an arm was); the first such, or -1. Each person is looked at in their box."""
        if not self._last_masks or self._last_z.shape != g.z.shape:
            return np.full(count, -1)
        whose = np.full(count, -1)
        for j, mask in reversed(list(enumerate(self._last_masks))):
            box = bounding_box(mask)
            z = g.z[box]
            same = mask[box] & (np.abs(z - self._last_z[box]) < self._edge(z))
            whose[np.bincount(labels[box][same], minlength=count) / n > 0.3] = j
        whose[0] = -1
        return whose

    def _whole(self, g: Grid, labels: np.ndarray, people: np.ndarray, whose: np.ndarray,
               mean_z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Something in front of a person (their arm across the body, someone passing) cuts them into
        pieces along its depth edges: the surfaces that were one person a frame ago, cut off by
        something nearer and within a body's thickness of each other (`BODY_DEPTH_MM`), are one person
        still, not several, nor left out of the body. Two people who were one surface for a frame, side
        by side or one behind the other, are two again: the background between them, or a body's
        thickness. The people picked, less such pieces of one picked before them, and for each surface
        the person (index among them) it is a piece of, or -1."""
        piece_of = np.full(whose.size, -1)
        kept: list[int] = []
        for p in people.tolist():  # Python ints (`_indices`)
            if piece_of[p] >= 0:
                continue
            piece_of[p] = len(kept)
            others = [q for q in _indices(whose == whose[p]) if q != p] if whose[p] >= 0 else []
            depth = median(g.z[labels == p]) if others else None
            for q in others:
                piece = labels == q
                if abs(median(g.z[piece]) - depth) < BODY_DEPTH_MM and self._in_front_of(g, piece, mean_z[q]):
                    piece_of[q] = len(kept)
            kept.append(p)
        return np.array(kept, dtype=people.dtype), piece_of

    def _in_front_of(self, g: Grid, surface: np.ndarray, depth: float) -> bool:
        """Is there something nearer than a depth edge in front of `surface` (at `depth`), within two
        cells of it (past the band its edge cuts)?"""
        box = bounding_box(surface, 2)
        around = cv2.dilate(surface[box].view(np.uint8), RING).view(bool)
        z = g.z[box]
        return bool(np.any(around & (z > 0) & (z < self._nearer_than(depth))))

    def _edge(self, depth: float | np.ndarray) -> float | np.ndarray:
        """The depth jump that separates two surfaces at `depth` (mm, a number or an array)."""
        return self.options.edge_mm + self.options.edge_ratio * depth

    def _nearer_than(self, depth: float) -> float:
        """Readings nearer than this are in front of a surface at `depth`, across a depth edge."""
        return depth - self._edge(depth)


def _boxes(labels: np.ndarray, which: np.ndarray) -> np.ndarray:
    """One row (x, y, w, h) per label: the bounding box of each label in `which`, zeros for the
    rest (only the few surfaces that could be people need one)."""
    boxes = np.zeros((len(which), 4), np.int64)
    for k in _indices(which):
        boxes[k] = cv2.boundingRect((labels == k).view(np.uint8))
    return boxes


def _indices(which: np.ndarray) -> list[int]:
    """Where `which` is true, as Python ints: surface labels to compare the label image with (an
    int32 image compared with a numpy int64 is first converted whole to int64)."""
    return np.flatnonzero(which).tolist()


def _labelled(labels: np.ndarray, which: list[int]) -> np.ndarray:
    """The cells of any of the labels `which`. A person is one surface or a few: comparing the
    labels with each costs less than looking up every cell's owner."""
    mask = labels == which[0]
    for k in which[1:]:
        mask |= labels == k
    return mask


def _per_surface(flat: np.ndarray, count: int, *weights: np.ndarray) -> list[np.ndarray]:
    """Per label of the flattened label image `flat`: its cells, and the sum
    of each of `weights` (arrays of the image's shape) over them, in float64.

    Summed over the runs of one label along the rows first, then per label: a surface's cells lie
    in runs, and bincount adding cell after cell into one bin waits each time for the addition
    before (twice as slow on these images). The depths and their squares are whole numbers, so
    their sums are exact either way."""
    starts = np.concatenate(([0], np.flatnonzero(flat[1:] != flat[:-1]) + 1))
    label = flat[starts].astype(np.intp)  # bincount's index type: converted once for all of them
    cells = np.bincount(label, weights=np.diff(starts, append=flat.size), minlength=count).astype(np.int64)
    return [cells] + [np.bincount(label, weights=np.add.reduceat(w.ravel(), starts, dtype=np.float64), minlength=count)
                      for w in weights]


def height_above(plane: np.ndarray, x, y, z):
    """The height (mm) above `plane` (nx, ny, nz, d) of the point(s) x, y, z (mm; numbers or arrays, whose
    dtype is kept: a grid's cells stay float32)."""
    nx, ny, nz, d = (float(v) for v in plane)
    return x * nx + y * ny + z * nz + d


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Row-wise cross product of (n, 3) arrays (np.cross costs more than the arithmetic on a few dozen rows)."""
    return np.stack([u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1],
                     u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2],
                     u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]], axis=1)
