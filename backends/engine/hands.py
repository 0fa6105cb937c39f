"""Hand candidates: the ends of the limbs that stick out of the body frame.

A cell of the user is "extended" when it is in front of the trunk (push, click; before the face,
in front of the face, so a head leaning forward is not a hand), beside it (swipe, arms spread)
or above the shoulders away from the head (wave, hand raise), and above the hips (legs are not
hands). Each connected patch of extended cells is one arm; its hand is the centre of the cells
within a palm's reach of the patch's point farthest from where the patch joins the rest of the
body without a depth jump (the elbow of a raised forearm, the shoulder of an outstretched arm),
so a bent or crossing arm still ends in its hand. An arm has one hand: of two ends on one side
of the spine the one farther from that side's shoulder is kept, an end beside and behind the
trunk within an upper arm of its shoulder is an elbow, and an end within a forearm of the base
of the neck is the head or a shoulder seen at an angle. An arm that nowhere stands that far out
(a hand at the chest, a push about to start) is extended from a lower threshold in front of the
chest, if it stands out of the body beside it by an arm's thickness and does not run up into the
head; so close to the body its whole edge joins it, so its hand is its most forward end. An arm
that does reach farther is judged by its extended cells alone: its upper arm in front of the
chest would move where the patch joins the body (and, touching the head, flip the hand to the
elbow). All in mm.
"""
from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from backends.engine.anatomy import Anatomy
from backends.engine.trunk import Body
from backends.engine.segmentation import ONE_CELL_GAP, Grid, Segment
from backends.engine.vectors import distance


#: (each cell, its neighbour) as slices of a grid: the neighbours below, above, right and left (for
#: the near path; `_attached`, run every frame, shares each axis's depth difference between two)
NEIGHBOURS = ((np.s_[1:, :], np.s_[:-1, :]), (np.s_[:-1, :], np.s_[1:, :]),
              (np.s_[:, 1:], np.s_[:, :-1]), (np.s_[:, :-1], np.s_[:, 1:]))


class HandOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    front_mm: float = Field(120, gt=0, description=(
        "in front of the trunk's surface (before the face, the face's) by more than this: extended"))
    near_front_mm: float = Field(90, gt=0, description=(
        "an arm that nowhere stands `front_mm` out is extended where it stands this far in front of the "
        "trunk's upper half (a hand at the chest, a push about to start); its hand is its most forward end"))
    arm_edge_mm: float = Field(60, ge=0, description=(
        "an arm found from `near_front_mm` stands somewhere this far out of the body cells beside it (a "
        "fist or forearm is 50-80 mm thick; a trunk leaning towards the camera is one smooth surface)"))
    beside_mm: float = Field(340, gt=0, description="farther than this sideways from the spine: extended")
    above_shoulder_mm: float = Field(150, description="higher than this above the shoulder line and clear of the head")
    head_clearance_mm: float = Field(190, gt=0, description="cells this close to the head joint are head, not hand")
    palm_radius_mm: float = Field(120, gt=0, description="cells this close to the fingertips make up the hand")
    palm_area_m2: float = Field(0.01, gt=0, description="frontal area of a hand and wrist: a hand seen whole has confidence 1")
    min_area_m2: float = Field(0.003, gt=0, description="smaller patches are noise, not a hand")
    hand_depth_mm: float = Field(25, ge=0, description="the hand joint lies this far behind the hand's surface")
    hip_margin_mm: float = Field(60, ge=0, description="a limb whose far end reaches this close to the hip line hangs down")
    joint_step_mm: float = Field(100, gt=0, description="neighbours closer than this in depth are one surface (arm joins body)")
    hands_apart_mm: float = Field(150, gt=0, description="two hand positions closer than this are one hand")
    min_reach_mm: float = Field(250, ge=0, description=(
        "an end nearer than this to the base of the neck is the head or a shoulder seen at an angle, "
        "not a hand (a hand out of its rest is at least a forearm away)"))
    second_hand_ratio: float = Field(0.8, gt=0, le=1, description=(
        "a second end of one patch counts as a hand when it reaches this share of the first's "
        "distance from the body (an elbow reaches about half)"))
    shoulder_half_width_mm: float = Field(180, gt=0, description=(
        "shoulder joints this far either side of the spine: of two ends on one side, the hand is "
        "the one farther from that shoulder (the other is its elbow)"))
    elbow_reach_mm: float = Field(370, gt=0, description=(
        "an end below the shoulders, behind the spine and this close to its shoulder joint is an "
        "elbow sticking out (hands on the hips, a forearm lifting in front of the body), not a hand"))
    max_hands: int = Field(2, ge=1)


@dataclass(frozen=True, eq=False)
class Candidate:
    position: np.ndarray  # mm
    reach: float  # mm from the base of the neck: how extended the arm is
    at_border: bool  # the hand touches the edge of the image
    root: np.ndarray  # where the arm joins the body (mm): tells left from right when arms cross
    confidence: float  # how much of a palm's area the sensor saw there, in [0, 1]
    loose: bool = False  # its patch joins the body nowhere without a depth jump (a hand seen apart from its arm)


class HandDetector:
    def __init__(self, options: HandOptions) -> None:
        self.options = options
        self.anatomy = Anatomy(options)

    def detect(self, seg: Segment, body: Body) -> list[Candidate]:
        o = self.options = self.anatomy.at(body.scale)  # the body's size: a child's arms and palms
        # Only the user's cells count, and the gap bridging reaches two cells out: the user's box
        # that much wider is all there is to look at.
        box, g, mask = body.user.box, body.user.grid, body.user.mask
        cand, near = self._extended(g, mask, body.core, body)
        if not cand.any():
            return []
        # One-cell gaps (dropped readings) do not cut an arm in two; the gap cells stay out of it.
        bridged = cv2.morphologyEx(cand.view(np.uint8), cv2.MORPH_CLOSE, ONE_CELL_GAP)
        count, labels = cv2.connectedComponents(bridged, connectivity=8)
        labels[~cand] = 0
        attached = self._attached(cand, mask & ~cand, g.z)
        neck = np.array([float(body.torso[0]), body.shoulder_y, body.torso[2]])
        border = _border(box, mask.shape, seg.mask.shape)
        found: list[Candidate] = []
        for label in range(1, count):
            cells = np.flatnonzero(labels == label)  # flat indices: faster to take by than rows and columns
            area = g.pixel_area_mm2.take(cells)
            if area.sum() < o.min_area_m2 * 1e6:
                continue
            pts = _points(g, cells)
            joint = attached.take(cells)
            joined = bool(joint.any())
            on_border = border.take(cells) if border is not None else None
            root = _mean(pts[joint]) if joined else neck
            tips, from_tips = self._tips(pts, root, at_chest=bool(near.take(cells).all()))
            for i, tip in enumerate(tips):
                if pts[tip, 1] < body.hip_y + o.hip_margin_mm and body.surface_z - pts[tip, 2] < o.front_mm:
                    continue  # the limb goes on below the hips at the body's side: a hanging arm
                palm = from_tips[i] <= o.palm_radius_mm
                if len(tips) > 1:  # keep each hand's palm on its own side of the other hand
                    palm &= from_tips[1 - i] > from_tips[i]
                position = _mean(pts[palm]) + (0.0, 0.0, o.hand_depth_mm)
                if self._elbow(position, body, neck):
                    continue
                at_border = on_border is not None and bool(on_border[palm].any())
                reach = distance(pts[tip], neck)
                if reach < o.min_reach_mm:
                    continue
                # Sides: by where the arm joins the body; for two hands of one patch, by each hand.
                seen = area[palm].sum() / (o.palm_area_m2 * 1e6)
                found.append(Candidate(position, reach, at_border,
                                       root if joined and len(tips) == 1 else position, min(1.0, seen),
                                       loose=not joined))
        found = self._one_per_arm(found, neck)
        found.sort(key=lambda c: -c.reach)
        kept: list[Candidate] = []
        for c in found:  # two patches of one arm (cut by the head's clearance) are one hand
            if all(distance(c.position, k.position) > o.hands_apart_mm for k in kept):
                kept.append(c)
        return kept[: o.max_hands]

    def _extended(self, g: Grid, mask: np.ndarray, core: np.ndarray, body: Body) -> tuple[np.ndarray, np.ndarray]:
        """The extended cells of the user (see the module doc), and those of them that are so only
        as an arm at the chest (extended from `near_front_mm`)."""
        o = self.options
        front, before_face = body.surface_z - g.z, body.face_z - g.z
        hx, hy = g.x - float(body.head[0]), g.y - float(body.head[1])
        head_clear = hx * hx + hy * hy > o.head_clearance_mm ** 2
        out = ((np.abs(g.x - float(body.torso[0])) > o.beside_mm) & ~core) | \
            ((g.y > body.shoulder_y + o.above_shoulder_mm) & head_clear)
        above_legs = mask & (g.y > body.hip_y)
        cand = above_legs & (out | self._before(front, before_face, head_clear, o.front_mm))
        chest = mask & (g.y > (body.shoulder_y + body.hip_y) / 2)  # the trunk's upper half and above
        near = chest & self._before(front, before_face, head_clear, o.near_front_mm) & ~cand
        if near.any():
            near = self._only_near(cand, near, mask, g.z, g.pixel_area_mm2, mask & ~head_clear)
            cand |= near
        return cand, near

    def _tips(self, pts: np.ndarray, root: np.ndarray, at_chest: bool) -> tuple[list[int], list[np.ndarray]]:
        """The hands of one arm's patch (indices into `pts`): its end farthest from where it joins
        the body, and a second end for two hands out together; and each point's distance from
        each of them (where their palms are)."""
        if at_chest:
            # An arm at the chest lies within a joint's step of it all along its edge: where it
            # joins the body says nothing. Its hand is its most forward end (a push starts there).
            tip = int(np.argmin(pts[:, 2]))
            return [tip], [_distances(pts, pts[tip])]
        o = self.options
        from_root = _distances(pts, root)
        tips = [int(np.argmax(from_root))]
        from_tips = [_distances(pts, pts[tips[0]])]
        # Both hands out together (a two-handed push) can make one patch: a second end as far
        # from where the patch joins the body, and a hand's width away from the first, is a hand.
        apart = from_tips[0] > o.hands_apart_mm
        if apart.any():
            second = int(np.argmax(np.where(apart, from_root, -1.0)))
            if from_root[second] >= o.second_hand_ratio * from_root[tips[0]]:
                tips.append(second)
                from_tips.append(_distances(pts, pts[second]))
        return tips, from_tips

    @staticmethod
    def _before(front: np.ndarray, before_face: np.ndarray, head_clear: np.ndarray, mm: float) -> np.ndarray:
        """Cells more than `mm` in front of the trunk (near the head, in front of the face)."""
        return (front > mm) & (head_clear | (before_face > mm))

    def _only_near(self, cand: np.ndarray, near: np.ndarray, mask: np.ndarray, z: np.ndarray,
                   area_mm2: np.ndarray, head: np.ndarray) -> np.ndarray:
        """The patches of `near` cells that are arms at the chest: joined to no patch of extended
        cells big enough to be a hand (an arm that reaches farther is judged by its extended cells
        alone: its upper arm in front of the chest would move where the patch joins the body, and so
        its hand), not running up into the head (a chin or throat ahead of a trunk walking in), and
        somewhere standing an arm's thickness out of the body cells beside them (a trunk leaning or
        moving towards the camera ahead of its estimated surface is one smooth surface)."""
        o = self.options
        count, patches = cv2.connectedComponents(cand.view(np.uint8), connectivity=8)
        area = np.bincount(patches[cand], weights=area_mm2[cand], minlength=count)
        hands = cand & (area >= o.min_area_m2 * 1e6)[patches]
        count, arms = cv2.connectedComponents((cand | near).view(np.uint8), connectivity=8)
        other = np.zeros(count, bool)  # arms reaching farther, or running into the head
        other[arms[hands]] = True
        other[arms[cv2.dilate(head.view(np.uint8), ONE_CELL_GAP).view(bool)]] = True
        # How far the body cells beside each near cell lie behind it: on the near cells' box and
        # one cell around it, not on all the user's.
        left, top, width, height = cv2.boundingRect(near.view(np.uint8))
        around = np.s_[max(top - 1, 0):top + height + 1, max(left - 1, 0):left + width + 1]
        depth, near_here = z[around], near[around]
        behind = mask[around] & ~(cand[around] | near_here)
        step = np.zeros(depth.shape, np.float32)
        for cell, beside in NEIGHBOURS:
            step[cell] = np.maximum(step[cell], np.where(behind[beside], depth[beside] - depth[cell], 0))
        stands_out = np.zeros(count, bool)  # somewhere an arm's thickness out of the body beside it
        stands_out[arms[around][near_here & (step >= o.arm_edge_mm)]] = True
        return near & (stands_out & ~other)[arms]

    def _shoulder(self, x: float, neck: np.ndarray) -> np.ndarray:
        """The shoulder joint on the side of the body where x is."""
        return neck + (np.copysign(self.options.shoulder_half_width_mm, x - neck[0]), 0.0, 0.0)

    def _elbow(self, position: np.ndarray, body: Body, neck: np.ndarray) -> bool:
        """Below the shoulders, behind the spine and within an upper arm of the shoulder: an elbow."""
        near = distance(position, self._shoulder(position[0], neck)) < self.options.elbow_reach_mm
        return bool(position[1] < body.shoulder_y and position[2] > body.torso[2] and near)

    def _one_per_arm(self, found: list[Candidate], neck: np.ndarray) -> list[Candidate]:
        """An arm has one hand: of the ends joined to the body on one side of the spine (a
        forearm in front and its elbow sticking out beside the body), the one farthest from that
        side's shoulder joint."""
        best: dict[bool, tuple[float, Candidate]] = {}
        for c in found:
            right = bool(c.root[0] > neck[0])
            d = distance(c.position, self._shoulder(c.root[0], neck))
            if right not in best or d > best[right][0]:
                best[right] = (d, c)
        return [c for _, c in best.values()]

    def _attached(self, cand: np.ndarray, rest: np.ndarray, z: np.ndarray) -> np.ndarray:
        """Candidate cells joined to the rest of the body without a depth jump: where each arm starts."""
        out = np.zeros_like(cand)
        near_y = np.abs(z[1:, :] - z[:-1, :]) < self.options.joint_step_mm  # per axis once: every frame
        near_x = np.abs(z[:, 1:] - z[:, :-1]) < self.options.joint_step_mm
        out[1:, :] |= rest[:-1, :] & near_y
        out[:-1, :] |= rest[1:, :] & near_y
        out[:, 1:] |= rest[:, :-1] & near_x
        out[:, :-1] |= rest[:, 1:] & near_x
        return out & cand


def _border(box: tuple[slice, slice], size: tuple[int, int], shape: tuple[int, int]) -> np.ndarray | None:
    """The cells of `box` (holding `size` cells of a grid of `shape`) on the grid's edge (the
    image's, where the user reaches it); None when the box reaches no edge."""
    top, left = box[0].start, box[1].start
    edges = (top == 0, top + size[0] == shape[0], left == 0, left + size[1] == shape[1])
    if not any(edges):
        return None
    border = np.zeros(size, bool)
    for edge, cells in zip(edges, (np.s_[0, :], np.s_[-1, :], np.s_[:, 0], np.s_[:, -1])):
        if edge:
            border[cells] = True
    return border


def _points(g: Grid, cells: np.ndarray) -> np.ndarray:
    """The positions of the grid's cells (flat indices) as (n, 3) float64 (filled column by
    column: np.stack costs more)."""
    pts = np.empty((len(cells), 3))
    pts[:, 0], pts[:, 1], pts[:, 2] = g.x.take(cells), g.y.take(cells), g.z.take(cells)
    return pts


def _mean(pts: np.ndarray) -> np.ndarray:
    """pts.mean(axis=0) (the same floats: the sum over the count) without its wrapper's cost."""
    return pts.sum(axis=0) / len(pts)


def _distances(pts: np.ndarray, point: np.ndarray) -> np.ndarray:
    """np.linalg.norm(pts - point, axis=1): the same floats, without its generality's cost."""
    d = pts - point
    return np.sqrt((d * d).sum(axis=1))
