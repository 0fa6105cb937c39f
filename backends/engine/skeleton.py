"""One user's skeleton from depth: head, neck, torso, shoulders, elbows, both hands, centre of mass.

The body frame (trunk.py) gives the spine, the shoulder line and the head; the hand tracker gives
the hands that stick out of the body. What is left is the hand at rest, and it is measured, not
placed: a hanging arm is the outermost part of the silhouette on its side below the elbow, out
beyond the thighs (by `beside_legs_mm`); going down it, the fingers end where the outline steps
in (or where it is no wider than the legs), and the hand is the outer part of the rows just above.
A hand held in front of the lower body (hands clasped) is the lowest part of the user on its side
standing out of the trunk's plane. A seated performer's knee sticks out like a hand: an extended
hand below the hips with a hand found beside the legs next to it is the knee, and the hand rests
there. A side where nothing shows keeps its hand where it was last measured, with confidence 0
(and has none before its first measurement: nothing is placed by guesswork). Elbows are reported where the depth has the arm between shoulder and hand;
otherwise they are left out.

Each side's hand has one id for as long as the user is in view (`hand_id(user, side)` of
backends/users.py), so a hand that comes down and goes up again stays the same hand; `extended`
says whether it sticks out of the body. Left and right are the performer's. All in mm.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from backends.engine.anatomy import Anatomy
from backends.engine.quantiles import median
from backends.engine.segmentation import Grid
from backends.engine.trunk import Body
from backends.engine.vectors import distance
from backends.users import hand_id
from host import Hand, HandState, Joint, Side, Vec3


class SkeletonOptions(BaseModel):
    """Anatomy in mm, the same for every performer."""

    model_config = ConfigDict(extra="forbid")
    forearm_below_shoulder_mm: float = Field(400, gt=0, description=(
        "a hanging hand is lower than this below the shoulder line (above it, the outline is the upper arm)"))
    arm_length_mm: float = Field(750, gt=0, description="a hand is no farther than this below its shoulder")
    beside_legs_mm: float = Field(40, ge=0, description=(
        "a hanging arm's rows stick out this much farther sideways than the legs below them"))
    legs_below_hips_mm: tuple[float, float] = Field((400, 700), description=(
        "the rows (mm below the hip line) whose outline is the thighs' width"))
    legs_half_width_mm: float = Field(170, gt=0, description="the thighs' outer edge from the spine, when no legs are seen")
    knee_above_hips_mm: float = Field(100, description=(
        "an extended hand lower than this above the hip line, with a hand found beside the legs on "
        "its side, is a seated performer's knee"))
    behind_mm: float = Field(150, gt=0, description=(
        "cells farther than this behind the trunk's surface are not an arm (a chair, a wall beside the user)"))
    fingertip_step_mm: float = Field(40, gt=0, description=(
        "going down a hanging arm, the outline stepping in by this much is where the fingers end"))
    palm_height_mm: float = Field(50, gt=0, description="the hand: the rows this far above the fingertips")
    palm_width_mm: float = Field(100, gt=0, description="and within this much of the outline's outer edge")
    in_front_mm: float = Field(70, ge=0, description=(
        "a hand held before the lower body stands out of the trunk's plane by more than this"))
    hand_depth_mm: float = Field(40, ge=0, description="a resting hand's joint lies this far behind its surface")
    joint_depth_mm: float = Field(110, ge=0, description="shoulder and elbow joints lie this far behind the surface")
    shoulder_half_width_mm: tuple[float, float] = Field((140, 230), description=(
        "the shoulder joint lies this far from the spine (at least, at most), inside the outline's edge"))
    shoulder_inside_edge_mm: float = Field(60, ge=0, description="the shoulder joint lies this far inside the outline")
    upper_arm_mm: tuple[float, float] = Field((200, 400), description=(
        "an elbow is this far from its shoulder; arm cells found elsewhere are not an elbow"))
    palm_area_m2: float = Field(0.01, gt=0, description="frontal area of a hand and wrist: a hand seen whole has confidence 1")
    resting_confidence: float = Field(0.8, ge=0, le=1, description="a resting hand's confidence at most: it touches the body")


@dataclass(frozen=True)
class Skeleton:
    """One user's joints (host.JOINTS names), both hands and centre of mass in one frame."""

    joints: dict[str, Joint]
    hands: tuple[Hand, ...]
    center_of_mass: Vec3 | None


@dataclass
class _SideHand:
    position: Vec3 | None = None  # last hand position
    reported: bool = False


@dataclass
class SkeletonEstimator:
    """Per user: the skeleton of each frame, and each side's hand id and lifecycle."""

    options: SkeletonOptions
    user_id: int = 1
    _sides: dict[Side, _SideHand] = field(default_factory=lambda: {Side.LEFT: _SideHand(), Side.RIGHT: _SideHand()})

    def __post_init__(self) -> None:
        self.anatomy = Anatomy(self.options)

    def estimate(self, body: Body, extended: tuple[Hand, ...], mirrored: bool) -> Skeleton:
        """This frame's skeleton. `extended`: the tracker's hands that stick out of the body (in view
        or held), whose sides are the performer's."""
        o = self.options = self.anatomy.at(body.scale)  # a child's limbs
        view = _View.of(body, o)
        torso = body.torso
        neck = np.array([torso[0], body.shoulder_y, torso[2]])
        joints = {"head": Joint(_vec(body.head), 1.0), "neck": Joint(_vec(neck), 1.0), "torso": Joint(_vec(torso), 1.0)}
        hands = []
        for side in (Side.LEFT, Side.RIGHT):
            outwards = 1.0 if (side is Side.RIGHT) == mirrored else -1.0  # image right is +x
            name = side.value
            cells = self._side_view(view, outwards)
            shoulder = self._shoulder(view, cells, body, outwards)
            joints[f"{name}_shoulder"] = Joint(_vec(shoulder), 0.8)
            position, confidence, is_out, at_border = self._side_hand(view, cells, body, side, outwards, extended)
            if position is None:
                continue  # not seen yet: no hand is placed where none was measured
            joints[f"{name}_hand"] = Joint(_vec(position), confidence)
            elbow = self._elbow(view, shoulder, position)
            if elbow is not None:
                joints[f"{name}_elbow"] = elbow
            hands.append(self._hand(side, position, confidence, is_out, at_border))
        g = view.grid
        n = np.count_nonzero(view.mask)
        mass = tuple(float(c[view.mask].sum() / n) for c in (g.x, g.y, g.z))
        return Skeleton(joints, tuple(hands), mass)

    def _side_hand(self, view: _View, cells: _Side, body: Body, side: Side, outwards: float,
                   extended: tuple[Hand, ...]) -> tuple[np.ndarray | None, float, bool, bool]:
        """This side's hand: (position, confidence, extended, touching the image's border); where it
        was last measured, with confidence 0, when the depth does not show it now; None before it
        was ever measured."""
        out = [h for h in extended if h.side is side and h.in_view]
        # Only extended hands below the hips can be a knee: with one higher up, what rests beside
        # the legs is not looked for (the extended hand is this side's hand).
        low = all(h.position[1] < body.hip_y + self.options.knee_above_hips_mm for h in out)
        found = self._resting(view, cells, body) if low else None
        if out and found is not None and found[2] and self._knee(out, found[0]):
            # The hand rests on the knee or beside it: between the knee's depth and the outline's.
            knee_z = min(h.position[2] for h in out)
            found = (np.array([found[0][0], found[0][1], 0.5 * (found[0][2] + knee_z)]), *found[1:])
            out = []
        if out:
            hand = max(out, key=lambda h: h.confidence)
            return np.asarray(hand.position), hand.confidence, True, hand.state is HandState.TOUCHING_FOV
        if found is not None:
            return found[0], found[1], False, False
        last = self._sides[side].position
        return (None if last is None else np.asarray(last)), 0.0, False, False

    def held(self, extended: tuple[Hand, ...]) -> tuple[Hand, ...]:
        """A frame without the user's body (a dropout shorter than the tracker's hold): each hand
        reported so far, the tracker's held extended hand on its side, else where it was last seen."""
        out = []
        for side, state in self._sides.items():
            if not state.reported or state.position is None:
                continue
            mine = [h for h in extended if h.side is side and h.in_view]
            if mine:
                out.append(self._hand(side, np.asarray(mine[0].position), mine[0].confidence, True, False))
            else:
                out.append(self._hand(side, np.asarray(state.position), 0.0, False, False))
        return tuple(out)

    def lost(self) -> tuple[Hand, ...]:
        """The user is gone: both hands LOST once, where they were last seen; ids stay for a return."""
        out = []
        for side, state in self._sides.items():
            if state.reported and state.position is not None:
                state.reported = False
                out.append(Hand(hand_id(self.user_id, side), HandState.LOST, state.position, side,
                                self.user_id, 0.0, None))
        return tuple(out)

    def _hand(self, side: Side, position: np.ndarray, confidence: float, is_out: bool, at_border: bool) -> Hand:
        state = self._sides[side]
        status = HandState.TOUCHING_FOV if at_border else HandState.TRACKING
        if not state.reported:
            status = HandState.NEW
        state.reported = True
        state.position = _vec(position)
        return Hand(hand_id(self.user_id, side), status, _vec(position), side, self.user_id,
                    round(float(confidence), 3), is_out)

    # -- measurements --------------------------------------------------------------------------
    def _side_view(self, view: _View, outwards: float) -> _Side:
        """One side's cells (beside the spine, not behind the trunk) and its outline's outer edge per row."""
        out = outwards * view.dx
        cells = view.near & (out > 40)
        edge = (out * cells).max(axis=1)  # 0 in a row without cells (its cells are all > 40 out)
        seen = edge > 0
        edge[~seen] = -np.inf
        return _Side(out, cells, edge, seen)

    def _shoulder(self, view: _View, side: _Side, body: Body, outwards: float) -> np.ndarray:
        """On the shoulder line, inside the outline's outer edge there (an arm raised beside the
        head widens the outline: the anatomical bounds keep the joint on the trunk)."""
        o = self.options
        lo, hi = o.shoulder_half_width_mm
        edge = side.edge[view.shoulder_rows & side.seen]
        half = min(hi, max(lo, float(median(edge)) - o.shoulder_inside_edge_mm)) if edge.size else 0.5 * (lo + hi)
        return np.array([body.torso[0] + outwards * half, body.shoulder_y, body.surface_z + o.joint_depth_mm])

    def _knee(self, out: list[Hand], beside: np.ndarray) -> bool:
        """Extended hands below the hips (`knee_above_hips_mm`) with a hand found beside the legs
        next to them (within a forearm) are a seated performer's knee."""
        return all(distance(h.position, beside) < self.options.upper_arm_mm[1] for h in out)

    def _resting(self, view: _View, side: _Side, body: Body) -> tuple[np.ndarray, float, bool] | None:
        """The hand at the lowest end of the arm beside the legs, else the lowest part of the user
        on this side held in front of the trunk's plane; None when the depth shows neither. The
        flag says whether it was found beside the legs."""
        o, g, rows_y, edge = self.options, view.grid, view.rows_y, side.edge
        # The legs' outer edge: the median over the thighs' rows, where legs are seen.
        legs = edge[view.thigh_rows & side.seen]
        legs_edge = float(median(legs)) if legs.size >= 3 else o.legs_half_width_mm
        arm_rows = np.flatnonzero(view.forearm_rows & (edge > legs_edge + o.beside_legs_mm))
        beside = arm_rows.size > 0
        if beside:
            tip = float(rows_y[self._fingertips(edge, arm_rows)])
            band = _rows(rows_y, tip - 1, tip + o.palm_height_mm)
            out = side.out[band]
            palm = side.cells[band] & (out >= edge[band, None] - o.palm_width_mm) & (out > legs_edge)
        else:
            # Before the lower body: the lowest cells of this side in front of the trunk's plane.
            band = _rows(rows_y, body.shoulder_y - o.arm_length_mm, body.shoulder_y - o.forearm_below_shoulder_mm)
            front = side.cells[band] & (body.surface_z - g.z[band] > o.in_front_mm)
            if not front.any():
                return None
            low = int(np.flatnonzero(front.any(axis=1))[-1])
            band = _rows(rows_y, rows_y[band][low] - 1, rows_y[band][low] + o.palm_height_mm)
            palm = side.cells[band] & (body.surface_z - g.z[band] > o.in_front_mm)
        if not palm.any():
            return None
        z = g.z[band][palm]
        n = len(z)
        near = np.partition(z, n // 5)[n // 5]  # the hand's front, not the thigh beside it
        position = np.array([g.x[band][palm].sum() / n, g.y[band][palm].sum() / n, near + o.hand_depth_mm])
        seen = float(g.pixel_area_mm2[band][palm].sum()) / (o.palm_area_m2 * 1e6)
        return position, min(o.resting_confidence, seen), beside

    def _fingertips(self, edge: np.ndarray, rows: np.ndarray) -> int:
        """The grid row where the hanging arm ends: going down the first run of arm rows (a row
        or two may be missing), the last one before the outline steps in by `fingertip_step_mm`
        (the thigh below the fingers), else the run's last row. A few dozen rows: a loop over them
        costs less than array operations."""
        out, rows = edge[rows].tolist(), rows.tolist()
        step = self.options.fingertip_step_mm
        above = [-math.inf, -math.inf, out[0]]  # the outline in the (up to) three rows above
        last = rows[0]
        for row, here in zip(rows[1:], out[1:]):
            if row - last > 2 or max(above) - here > step:
                return last  # the run ends at a gap, or the outline steps in below this row
            above = [above[1], above[2], here]
            last = row
        return last

    def _elbow(self, view: _View, shoulder: np.ndarray, hand: np.ndarray) -> Joint | None:
        """The user's cell nearest the middle of shoulder and hand, if it is an upper arm from the
        shoulder and a forearm from the hand: the depth shows the arm there."""
        o, g = self.options, view.grid
        middle = 0.5 * (shoulder + hand)
        band = _rows(view.rows_y, middle[1] - 150, middle[1] + 150)
        x = g.x[band]
        near = view.mask[band] & (np.abs(x - middle[0]) < 150)
        if not near.any():
            return None
        cells = np.array((x[near], g.y[band][near], g.z[band][near]))  # (3, n): summed row by row below
        offset = cells - middle[:, None]
        x, y, z = cells[:, int(np.argmin((offset * offset).sum(axis=0)))].tolist()
        cell = (x, y, z + o.hand_depth_mm)
        lo, hi = o.upper_arm_mm
        upper, fore = distance(cell, shoulder), distance(cell, hand)
        if not (lo <= upper <= hi and lo <= fore <= hi):
            return None
        return Joint(cell, 0.5)


@dataclass(frozen=True)
class _View:
    """One frame's user on its user box, with what both sides share."""

    grid: Grid
    mask: np.ndarray
    dx: np.ndarray  # mm sideways from the spine (image right +)
    near: np.ndarray  # user cells not behind the trunk's surface (no chair, no wall beside the user)
    rows_y: np.ndarray  # each row's height (mm), NaN where the row has no user cell
    # the rows (both sides look at the same) ...
    shoulder_rows: np.ndarray  # ... of the shoulder joint's outline: at most 120 mm below the shoulder line
    thigh_rows: np.ndarray  # ... whose outline is the thighs' width
    forearm_rows: np.ndarray  # ... a hanging arm's lower part is looked for in

    @classmethod
    def of(cls, body: Body, o: SkeletonOptions) -> "_View":
        grid, mask = body.user.grid, body.user.mask  # the user's box, shared with the body frame and hands
        rows_y = _row_heights(grid.y, mask)
        legs_lo, legs_hi = body.hip_y - o.legs_below_hips_mm[1], body.hip_y - o.legs_below_hips_mm[0]
        top, bottom = body.shoulder_y - o.forearm_below_shoulder_mm, body.shoulder_y - o.arm_length_mm
        return cls(grid, mask, grid.x - float(body.torso[0]), mask & (grid.z - body.surface_z < o.behind_mm),
                   rows_y, np.abs(rows_y - (body.shoulder_y - 60)) < 60, (rows_y > legs_lo) & (rows_y < legs_hi),
                   (rows_y < top) & (rows_y > bottom))


@dataclass(frozen=True)
class _Side:
    out: np.ndarray  # mm outwards from the spine on this side
    cells: np.ndarray  # this side's cells of the view's `near`
    edge: np.ndarray  # per row, the outermost of them (-inf: none)
    seen: np.ndarray  # the rows holding some of them (a finite edge)


def _rows(rows_y: np.ndarray, low: float, high: float) -> slice:
    """The rows whose height lies in [low, high] (rows go down as the index grows)."""
    inside = ((rows_y >= low) & (rows_y <= high)).nonzero()[0]
    return slice(int(inside[0]), int(inside[-1]) + 1) if inside.size else slice(0, 0)


def _row_heights(y: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Each grid row's height in mm (the mean over its user cells; NaN for empty rows)."""
    counts = mask.sum(axis=1)  # np.count_nonzero along an axis costs twice as much
    sums = (y * mask).sum(axis=1)
    return np.where(counts > 0, sums / np.maximum(counts, 1), np.nan)


def _vec(a: np.ndarray) -> Vec3:
    return (float(a[0]), float(a[1]), float(a[2]))
