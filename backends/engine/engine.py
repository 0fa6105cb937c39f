"""The open engine for several people: segment once, tell people apart, then one pipeline per user.

Per frame: the segmenter finds every person on one shared grid (segmentation.py), the people
tracker gives each a stable id (people.py), and each user's own HandTracker (body frame, hand
tracks) and GestureRecognizer run on that user's segment alone, so two performers' strokes never
mix. Hand ids come from one count shared by all users (unique in a frame); with one performer the
hands, ids and gestures are those of the single-user tracker. A user hidden for now (behind
another) keeps their pipeline and is reported TRACKING, their two hands held where last seen,
until the people tracker says LOST; then their pipeline ends.

Each user's pipeline sees only the box around them on the shared grid, two cells wider (as far
as the body frame's openings and the hand detector's gap bridging look beyond the user, so every
result is the same as on the whole grid, image borders included): two users cost little more
than one.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from itertools import count
from typing import Mapping

import numpy as np
from pydantic import Field

from backends.engine.people import PeopleOptions, PeopleTracker
from backends.engine.recognizer import GestureRecognizer
from backends.engine.rules import GestureRules
from backends.engine.segmentation import BEYOND_USER, Segment, Segmenter, bounding_box
from backends.engine.tracker import HandTracker, TrackerOptions, TrackResult
from host import DepthFrame, Gesture, GestureType, Hand, HandState, Joint, User


class EngineOptions(TrackerOptions):
    """The tracker's options (mm, s) plus `people` (telling people apart) and `gestures`: overrides
    of any GestureRules threshold."""

    people: PeopleOptions = PeopleOptions()
    gestures: GestureRules = Field(default_factory=GestureRules,
                                   description="gesture thresholds (mm, s), e.g. {swipe_min_travel_mm = 300}")


@dataclass
class _Pipeline:
    """One user's own tracker and recogniser, and what was last reported of them."""

    tracker: HandTracker
    recognizer: GestureRecognizer
    user: User | None = None
    seen: float = 0.0


@dataclass(frozen=True)
class EngineFrame:
    """One frame of the engine: users, every user's hands (user_id set), gestures, per-user results."""

    users: tuple[User, ...]
    hands: tuple[Hand, ...]  # the extended hands the recognisers follow
    results: Mapping[int, TrackResult]  # user id -> that user's tracking (seen or hidden users)
    seen: frozenset[int] = frozenset()  # ids of the hands found in this frame
    user_hands: tuple[Hand, ...] = ()  # both hands of every user (skeleton.py), resting ones included
    gestures: tuple[Gesture, ...] = ()
    #: the users seen now as (user id, TrackResult), farthest first: the label image's drawing order
    drawn: list = field(default_factory=list, repr=False)

    def user_labels(self, depth: DepthFrame) -> np.ndarray:
        """uint8 (H, W) at the depth image's size: 0 nobody, else the id of the user seen there
        (a nearer user drawn over a farther one)."""
        labels = np.zeros((depth.height, depth.width), np.uint8)
        for uid, result in self.drawn:
            mask = result.full_mask(depth)
            if mask is not None:
                labels[mask] = uid
        return labels


class Engine:
    """Segmenter, people tracker and a tracker + recogniser per user for one stream of depth frames."""

    def __init__(self, options: EngineOptions, dictionary: Mapping[str, GestureType] | None) -> None:
        self.options, self.dictionary = options, dictionary
        self.segmenter = Segmenter(options.segmentation)
        self.people = PeopleTracker(options.people)
        self.pipelines: dict[int, _Pipeline] = {}
        self._hand_ids = count(1)
        self._ended: list[tuple[int, _Pipeline]] = []
        self.last: EngineFrame | None = None

    def step(self, depth: DepthFrame) -> EngineFrame:
        """Track, then each user's recogniser on that user's hands found in this frame."""
        frame, ended = self.track(depth), self._ended
        gestures: list[Gesture] = []
        t, mirrored = depth.timestamp, depth.mirrored
        for uid, pipeline in sorted(self.pipelines.items()) + ended:
            result = frame.results.get(uid)
            if result is None:  # LOST now: the recogniser judges what is pending, as at a lost hand
                hands, body = [h for h in frame.hands if h.user_id == uid], {}
            else:
                # A hand held where it was last seen (a dropout of a frame or two) is no measurement:
                # its standing still would read as a stop. The recogniser gets the hands found now.
                hands = [h for h in result.hands if h.id in result.seen or not h.in_view]
                body = result.body
            gestures += [replace(g, user_id=uid) for g in pipeline.recognizer.update(t, hands, body, mirrored)]
        frame = replace(frame, gestures=tuple(gestures))
        self.last = frame
        return frame

    def finish(self) -> list[Gesture]:
        """The source ended: each user's recogniser's pending swipes complete (GestureRecognizer.finish)."""
        return [replace(g, user_id=uid) for uid, p in sorted(self.pipelines.items()) for g in p.recognizer.finish()]

    def track(self, depth: DepthFrame) -> EngineFrame:
        """Tracking only (what the bench times); the pipelines of users LOST now wait in `_ended`
        for their recognisers' last word."""
        t, mirrored = depth.timestamp, depth.mirrored
        people = self.people.update(t, self.segmenter.people(depth))
        users, hands, both, results, seen, labels = [], [], [], {}, set(), []
        ended = self._ended = []
        for person in people:
            pipeline = self.pipelines.get(person.id)
            if pipeline is None:
                pipeline = self.pipelines[person.id] = self._pipeline(person.id)
            if person.state is HandState.LOST:
                ended.append((person.id, self.pipelines.pop(person.id)))
                hands += [replace(h, user_id=person.id) for h in pipeline.tracker.drop_all()]
                both += pipeline.tracker.skeleton.lost()
                if pipeline.user is not None:
                    users.append(replace(pipeline.user, state=HandState.LOST))
                continue
            segment = person.person.segment if person.person is not None else None
            box = self._box(segment)
            result = pipeline.tracker.track(box, t, mirrored)
            if segment is not None:
                result = replace(result, mask=segment.mask, grid_z=segment.grid.z)
            results[person.id] = result
            hands += [replace(h, user_id=person.id) for h in result.hands]
            both += result.user_hands  # the skeleton names them by its user
            seen |= result.seen
            user = self._user(person.id, box, result, pipeline, t)
            if user is not None:
                users.append(user)
            if person.person is not None:
                labels.append((person.centre[2], person.id, result))
        labels = [(uid, result) for _, uid, result in sorted(labels, key=lambda x: -x[0])]
        return EngineFrame(tuple(users), tuple(sorted(hands, key=lambda h: h.id)), results, frozenset(seen),
                           tuple(both), drawn=labels)

    @staticmethod
    def _box(segment: Segment | None) -> Segment | None:
        """The segment cut down to the user's box plus BEYOND_USER cells, clamped to the grid."""
        if segment is None:
            return None
        mask = segment.mask
        box = bounding_box(mask, BEYOND_USER)
        if box is None or mask[box].size >= 0.8 * mask.size:
            return segment
        return segment.crop(box)

    def _pipeline(self, uid: int) -> _Pipeline:
        # the user's hands are held while they are hidden, until the people tracker says LOST
        return _Pipeline(HandTracker(self.options, self._hand_ids, uid, user_timeout_s=float("inf")),
                         GestureRecognizer(self.options.gestures, self.dictionary))

    def _user(self, uid: int, segment: Segment | None, result: TrackResult, pipeline: _Pipeline,
              t: float) -> User | None:
        """The user as reported now: from this frame's body when seen (the skeleton's joints and
        centre of mass when it has them, else the body frame's torso and head and the segment's
        mean); hidden (behind someone, a dropout), still TRACKING until LOST, where last seen:
        after the hands' `hold_s`, with joint confidences 0 (NiTE's tracked but not visible)."""
        if segment is None or not result.body:
            if pipeline.user is None:
                return None
            user = replace(pipeline.user, state=HandState.TRACKING)
            if t - pipeline.seen > self.options.hold_s:
                user = replace(user, joints={name: Joint(j.position, 0.0) for name, j in user.joints.items()})
            return user
        g, mask = segment.grid, segment.mask
        mass = result.center_of_mass or (float(g.x[mask].mean()), float(g.y[mask].mean()), float(g.z[mask].mean()))
        joints = result.joints or {name: Joint(p) for name, p in result.body.items()}
        state = HandState.NEW if pipeline.user is None else HandState.TRACKING
        pipeline.user, pipeline.seen = User(uid, state, joints, mass), t
        return pipeline.user
