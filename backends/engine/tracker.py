"""The depth hand tracker of the open engine: segmentation -> body frame -> hand candidates -> tracks.

Tracks keep their id for as long as the hand is seen again within `lost_timeout_s`, go NEW ->
TRACKING -> LOST, and report TOUCHING_FOV while the hand touches the edge of the image. Left and
right are the performer's, fixed when a track is born (a right hand that swipes across the body
stays the right hand). Hysteresis keeps effects steady on noisy depth: a candidate becomes a
hand once seen again `confirm_s` later (at once when the sensor saw enough of a palm), a tracked
hand missed for up to `hold_s` is still reported where it was last seen (longer, it is left out
of the frame rather than reported where it was), and an arm has one hand: a candidate on the
side of a hand in view and nearer the body than it (an elbow sticking out during a swipe) is
not a new hand, nor is a piece cut off from a tracked arm next to its hand (a whole arm swinging
across the face shows as two loose pieces, the one left over on the far side of the spine); one
farther out is a hand only once seen again, however much of a palm it shows (an arm across the
face can show two ends), and a hand out of sight for longer than `hold_s` is not found again while
another hand of its side is in view (that is the side's hand now).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from itertools import count
from typing import Iterator

import cv2
import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from backends.engine.assignment import best_assignment
from backends.engine.hands import Candidate, HandDetector, HandOptions
from backends.engine.segmentation import Segment, SegmentationOptions, Segmenter
from backends.engine.skeleton import SkeletonEstimator, SkeletonOptions
from backends.engine.smoothing import OneEuroFilter, SmoothingOptions
from backends.engine.trunk import BodyEstimator, BodyOptions
from host import DepthFrame, Hand, HandState, Joint, Side, Vec3


class TrackerOptions(BaseModel):
    """Everything the tracker does, in mm and seconds."""

    model_config = ConfigDict(extra="forbid")
    lost_timeout_s: float = Field(0.5, ge=0, description="a hand unseen this long is LOST; seen again sooner, it keeps its id")
    max_speed_mm_s: float = Field(5000, gt=0, description="fastest plausible hand: gates matching across frames")
    match_slack_mm: float = Field(150, ge=0, description="matching distance allowed on top of max speed * dt")
    confirm_s: float = Field(0.03, ge=0, description=(
        "a new candidate becomes a hand when seen again this much later (one frame at 30 fps): "
        "a patch seen once is noise"))
    strong_confidence: float = Field(0.3, ge=0, le=1, description=(
        "a candidate this confident (the share of a palm the sensor saw) is a hand at once, unless another "
        "hand of its side is in view (then it waits `confirm_s` like any other)"))
    hold_s: float = Field(0.07, ge=0, description=(
        "a tracked hand missed for up to this long is still reported where it was last seen "
        "(two frames at 30 fps): a dropout does not make it flicker lost/new"))
    loose_hand_mm: float = Field(250, ge=0, description=(
        "a hand seen apart from its arm (no depth-continuous join to the body: a whole arm swinging across "
        "the face) within this of a tracked hand's find and farther out is that hand, the find nearer the "
        "body its forearm: a forearm's length. Any other loose find this close to a tracked hand is another "
        "piece of that arm, no new hand"))
    match_max_gap_s: float = Field(0.1, gt=0, description="the gate stops growing after this long unseen: "
                                   "a hand that reappears far away is a new hand")
    other_arm_mm: float = Field(100, ge=0, description=(
        "a hand out of sight for longer than `hold_s` is not found again in a candidate whose arm joins the "
        "body farther than this on the other side of the spine: that is the other arm's hand (followed "
        "frame to frame, a hand may cross the body)"))
    predict_s: float = Field(0.0, ge=0, le=0.2, description=(
        "report hands this far ahead along their velocity: compensates a show's output latency "
        "(projector, renderer) so effects land on the hands; 0 reports where the hand was seen"))
    smoothing: SmoothingOptions = SmoothingOptions()
    body_smoothing: SmoothingOptions = SmoothingOptions(min_cutoff_hz=0.8, beta=0.002)
    segmentation: SegmentationOptions = SegmentationOptions()
    body: BodyOptions = BodyOptions()
    hands: HandOptions = HandOptions()
    skeleton: SkeletonOptions = SkeletonOptions()


@dataclass(frozen=True)
class TrackResult:
    """One frame's tracking: hands (performer's sides), body reference points in mm, the user's mask."""

    hands: tuple[Hand, ...]
    body: dict[str, Vec3]
    seen: frozenset[int] = frozenset()  # ids of the hands found in this frame (others are held or lost)
    mask: np.ndarray | None = None  # (h, w) bool on the internal grid; full_mask() for the image's size
    grid_z: np.ndarray | None = None  # the grid's depth (mm), to refine the mask at full resolution
    #: the user's joints (host.JOINTS names) and centre of mass; empty/None while no user is seen
    joints: dict[str, Joint] = field(default_factory=dict)
    center_of_mass: Vec3 | None = None
    #: both hands for as long as the user is in view (resting ones with extended False), one id
    #: per side; `hands` are the tracker's extended hands, which the recogniser follows
    user_hands: tuple[Hand, ...] = ()

    def full_mask(self, depth: DepthFrame, tolerance_mm: float = 250.0) -> np.ndarray | None:
        """The user's silhouette at the depth image's resolution (for silhouette effects): pixels
        of a user cell with a reading close to that cell's depth (not the wall seen beside it)."""
        if self.mask is None or self.grid_z is None:
            return None
        size = (depth.width, depth.height)
        near = cv2.resize(self.mask.view(np.uint8), size, interpolation=cv2.INTER_NEAREST).view(bool)
        z = cv2.resize(self.grid_z, size, interpolation=cv2.INTER_NEAREST)
        return near & (depth.data > 0) & (np.abs(depth.data - z) < tolerance_mm)


@dataclass(eq=False)
class _Track:
    id: int
    side: Side
    filter: OneEuroFilter
    position: np.ndarray  # as reported: smoothed (and predicted, with `predict_s`)
    found: np.ndarray  # where the hand was last found, unsmoothed
    born: float
    seen: float
    at_border: bool = False
    confidence: float = 1.0
    reported: bool = False
    confirmed: bool = False
    reach: float = 0.0  # how far out the hand was last seen (mm from the neck)


def _vec(a: np.ndarray) -> Vec3:
    return (float(a[0]), float(a[1]), float(a[2]))


class HandTracker:
    def __init__(self, options: TrackerOptions | None = None, ids: Iterator[int] | None = None,
                 user_id: int = 1, user_timeout_s: float | None = None) -> None:
        """`ids`: where hand ids come from (the engine's users share one count: ids stay unique);
        `user_id`: whose skeleton this is (its hands' ids are that user's); `user_timeout_s`: how
        long the user may be out of sight, both hands held where they were last seen, before the
        hands are LOST (default `lost_timeout_s`; the engine's people tracker decides instead)."""
        self.options = options or TrackerOptions()
        self.user_timeout_s = self.options.lost_timeout_s if user_timeout_s is None else user_timeout_s
        self.segmenter = Segmenter(self.options.segmentation)
        self.body_estimator = BodyEstimator(self.options.body, self.options.body_smoothing)
        self.detector = HandDetector(self.options.hands)
        self.skeleton = SkeletonEstimator(self.options.skeleton, user_id)
        self._user_seen: float | None = None
        self._tracks: list[_Track] = []
        self._ids = ids if ids is not None else count(1)

    def process(self, depth: DepthFrame) -> TrackResult:
        """One frame of the one user (the nearest person, stayed on while in view)."""
        return self.track(self.segmenter.segment(depth), depth.timestamp, depth.mirrored)

    def track(self, seg: Segment | None, t: float, mirrored: bool) -> TrackResult:
        """One user's frame from their segment (None: not seen in this frame)."""
        body = self.body_estimator.estimate(seg, t) if seg is not None else None
        if body is None:
            self.body_estimator.reset()
            hands = self._update_tracks(t, [], None, mirrored)
            unseen = t - self._user_seen if self._user_seen is not None else np.inf
            lost = unseen > self.user_timeout_s
            return TrackResult(hands, {}, user_hands=self.skeleton.lost() if lost else self.skeleton.held(hands))
        self._user_seen = t
        candidates = self.detector.detect(seg, body)
        hands = self._update_tracks(t, candidates, body.torso, mirrored)
        points = {"torso": _vec(body.torso), "head": _vec(body.head)}
        seen = frozenset(track.id for track in self._tracks if track.seen == t)
        skeleton = self.skeleton.estimate(body, hands, mirrored)
        return TrackResult(hands, points, seen, seg.mask, seg.grid.z, skeleton.joints, skeleton.center_of_mass,
                           skeleton.hands)

    # -- tracks ------------------------------------------------------------------------------
    def _update_tracks(self, t: float, found: list[Candidate], torso: np.ndarray | None,
                       mirrored: bool) -> tuple[Hand, ...]:
        """Follow the tracks the candidates continue, start new ones, and report the hands (those of
        ended tracks LOST), sorted by id."""
        matched = self._farthest_out(t, self._match(t, found, torso, mirrored), found)
        self._follow(t, matched)
        taken = list(matched.values())  # a piece of a tracked arm left over is no new hand
        free = [c for c in found if c not in taken and not any(self._piece_of(c, m) for m in taken)]
        out = self._admit(t, free, matched, torso, mirrored)
        out += self._report(t)
        return tuple(sorted(out, key=lambda h: h.id))

    def _follow(self, t: float, matched: dict[_Track, Candidate]) -> None:
        """Move the matched tracks to their candidates; a track seen once and not again is noise."""
        o = self.options
        for track, cand in matched.items():
            track.seen, track.at_border, track.confidence = t, cand.at_border, cand.confidence
            track.reach, track.found = cand.reach, cand.position
            track.position = track.filter(t, cand.position) + o.predict_s * track.filter.velocity
            track.confirmed = track.confirmed or t - track.born >= o.confirm_s
        for track in [tr for tr in self._tracks if not tr.confirmed and tr not in matched]:
            self._tracks.remove(track)  # a candidate seen once and not again: noise, never reported

    def _admit(self, t: float, free: list[Candidate], matched: dict[_Track, Candidate],
               torso: np.ndarray | None, mirrored: bool) -> list[Hand]:
        """New tracks for the unmatched candidates (farthest reach first) that are hands, not
        another part of an arm in view; the LOST hands of the tracks they replace."""
        o = self.options
        out: list[Hand] = []
        for cand in free:
            side = self._side_of(cand, torso, mirrored)
            same = [tr for tr in self._tracks if tr.side is side and side is not Side.UNKNOWN]
            in_view = [tr for tr in same if self._in_view(t, tr)]
            if any(cand.reach <= tr.reach for tr in in_view):
                continue  # on the side of a hand in view, nearer the body: another part of that arm
            for old in same:  # that side's hand, out of sight for a while, is found elsewhere: a new hand
                if old not in in_view:
                    out.extend(self._drop(old))
            if len(self._tracks) >= o.hands.max_hands:
                stale = [tr for tr in self._tracks if tr not in matched]
                if not stale:
                    break
                out.extend(self._drop(min(stale, key=lambda tr: tr.seen)))  # replaces the longest unseen
            # a second find on the side of a hand in view (an arm across the face can show two ends)
            # is a hand only once seen again, however much of a palm it shows
            self._tracks.append(self._birth(t, cand, side, sure=not in_view))
        return out

    def _report(self, t: float) -> list[Hand]:
        """Each track's hand now: LOST once out of sight too long, else NEW, TOUCHING_FOV or
        TRACKING while seen or held."""
        o = self.options
        out: list[Hand] = []
        for track in list(self._tracks):
            unseen = t - track.seen
            if unseen > o.lost_timeout_s:
                out.extend(self._drop(track))  # where it was last seen
                continue
            if not track.confirmed or unseen > o.hold_s or (unseen > 0 and not track.reported):
                continue  # out of sight for now: the id waits for the hand, nothing stale is reported
            if not track.reported:
                state = HandState.NEW
            elif track.at_border:
                state = HandState.TOUCHING_FOV
            else:
                state = HandState.TRACKING
            track.reported = True
            out.append(self._hand(track, state, track.confidence))
        return out

    def drop_all(self) -> tuple[Hand, ...]:
        """The user is gone: every hand ends now (LOST where last seen, those ever reported)."""
        return tuple(h for track in list(self._tracks) for h in self._drop(track))

    def _drop(self, track: _Track) -> list[Hand]:
        """End a track: LOST where it was last seen, if it was ever reported."""
        self._tracks.remove(track)
        return [self._hand(track, HandState.LOST, 0.0)] if track.reported else []

    def _match(self, t: float, found: list[Candidate], torso: np.ndarray | None,
               mirrored: bool) -> dict[_Track, Candidate]:
        """The assignment of candidates to live tracks with the smallest total distance, within gates
        and never across arms; a hand out of sight for longer than `hold_s` takes none while another
        hand of its side is in view (that is the side's hand now)."""
        tracks = self._tracks
        if not tracks or not found:
            return {}
        in_view = {tr.side for tr in tracks if self._in_view(t, tr) and tr.side is not Side.UNKNOWN}
        allowed: dict[tuple[int, int], float] = {}  # (track, candidate) -> distance, for pairs within gates
        for i, tr in enumerate(tracks):
            if not self._in_view(t, tr) and tr.side in in_view:
                continue
            gate = self._gate(t, tr)
            for j, c in enumerate(found):
                d = self._distance(tr, c)
                if d <= gate and not self._other_arm(t, tr, c, torso, mirrored):
                    allowed[i, j] = d
        return {tracks[i]: found[j] for i, j in best_assignment(allowed, len(tracks), len(found))}

    def _in_view(self, t: float, track: _Track) -> bool:
        """Is the track's hand seen now or held where it was last seen (missed for at most `hold_s`)?"""
        return t - track.seen <= self.options.hold_s

    def _gate(self, t: float, track: _Track) -> float:
        """How far from the track a candidate may be found: a hand's fastest move since it was seen."""
        o = self.options
        return o.match_slack_mm + o.max_speed_mm_s * min(t - track.seen, o.match_max_gap_s)

    @staticmethod
    def _distance(track: _Track, cand: Candidate) -> float:
        """From where the track's hand was last found or from its smoothed position, the nearer:
        smoothing lags a fast hand (a whole arm swinging back in a wave) and steadies a hand whose
        last find strayed."""
        return float(min(np.linalg.norm(track.found - cand.position), np.linalg.norm(track.position - cand.position)))

    def _farthest_out(self, t: float, matched: dict[_Track, Candidate],
                      found: list[Candidate]) -> dict[_Track, Candidate]:
        """The matches, each track moved on to a loose candidate left over that lies within its gate, a
        forearm from the candidate it matched and farther out: a whole arm swinging across the face can
        show its hand apart from the arm (taken for the other arm's) and the forearm nearer the last find."""
        for c in [c for c in found if c not in matched.values()]:
            for tr, m in matched.items():
                if c.reach > m.reach and self._piece_of(c, m) and self._distance(tr, c) <= self._gate(t, tr):
                    matched[tr] = c
                    break
        return matched

    def _piece_of(self, cand: Candidate, hand: Candidate) -> bool:
        """Is `cand` a piece of the arm whose hand was found at `hand`: seen apart from the body (loose)
        within a forearm's length (`loose_hand_mm`) of it? A whole arm swinging across the face shows so."""
        return cand.loose and float(np.linalg.norm(cand.position - hand.position)) <= self.options.loose_hand_mm

    def _birth(self, t: float, cand: Candidate, side: Side, sure: bool = True) -> _Track:
        track = _Track(next(self._ids), side, OneEuroFilter(self.options.smoothing), cand.position, cand.position,
                       t, t, cand.at_border, cand.confidence, reach=cand.reach)
        track.position = track.filter(t, cand.position)
        track.confirmed = self.options.confirm_s <= 0 or sure and cand.confidence >= self.options.strong_confidence
        return track

    def _other_arm(self, t: float, track: _Track, cand: Candidate, torso: np.ndarray | None, mirrored: bool) -> bool:
        o = self.options
        if (torso is None or track.side is Side.UNKNOWN or self._in_view(t, track)
                or abs(cand.root[0] - torso[0]) <= o.other_arm_mm):
            return False
        return self._side_of(cand, torso, mirrored) is not track.side

    @staticmethod
    def _side_of(cand: Candidate, torso: np.ndarray | None, mirrored: bool) -> Side:
        """The performer's side the arm joins the body on (where it starts, not where the hand
        is, so a hand first seen across the body gets its own side)."""
        if torso is None:
            return Side.UNKNOWN
        image_right = cand.root[0] > torso[0]
        return Side.RIGHT if image_right == mirrored else Side.LEFT

    @staticmethod
    def _hand(track: _Track, state: HandState, confidence: float) -> Hand:
        return Hand(track.id, state, _vec(track.position), track.side, 1, round(confidence, 3))
