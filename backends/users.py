"""Users rebuilt from skeletons (an OSC bridge's, MediaPipe's): lifecycle, bodies, both hands,
a recogniser each. Shared by the backends that get whole skeletons rather than depth.

A user is NEW in the first frame that reports it, TRACKING after, and LOST once: when the bridge
says so (`/lost_user`) or when its messages stop for `lost_timeout_s`. A user the bridge announced
but is still calibrating (OSCeleton's `/new_user` comes seconds before `/new_skel` and the
joints) waits up to CALIBRATING_S. Both hands are reported for as long as the user is, with
`extended` saying whether the hand sticks out of the body; ids are 10 * user + 1 (left) and
10 * user + 2 (right). Each user has its own GestureRecognizer, fed one sample per bridge frame
with both hands and the torso and head, so two performers' strokes never mix.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from typing import Callable, Mapping

import numpy as np

from host import DepthFrame, Gesture, Hand, HandState, Intrinsics, Joint, Side, User, Vec3

CALIBRATING_S = 30.0
HANDS = {Side.LEFT: ("left_hand", 1), Side.RIGHT: ("right_hand", 2)}
MASS = ("torso", "left_hip", "right_hip")  # a skeleton's centre of mass, roughly: the trunk's mean


def center_of_mass(joints: Mapping[str, Joint]) -> Vec3 | None:
    """A skeleton's centre of mass, roughly: the mean of its trunk joints (None without any)."""
    points = [joints[n].position for n in MASS if n in joints]
    return tuple(sum(c) / len(points) for c in zip(*points)) if points else None


def hand_id(user: int, side: Side) -> int:
    return 10 * user + HANDS[side][1]


def extended(hand: Vec3, torso: Vec3 | None, reach_mm: float) -> bool:
    """Whether a hand sticks out of the body: farther than `reach_mm` from the torso, counting
    only sideways, forwards and upwards (a hanging hand is far below the torso, and at rest)."""
    if torso is None:
        return True
    dx, dy, dz = hand[0] - torso[0], max(0.0, hand[1] - torso[1]), hand[2] - torso[2]
    return math.sqrt(dx * dx + dy * dy + dz * dz) > reach_mm


@dataclass
class _User:
    id: int
    recognizer: object
    last_seen: float  # arrival time (s, monotonic) of the last message about this user
    joints: dict[str, Joint] = field(default_factory=dict)
    sample_t: float | None = None  # source time of the newest sample
    reported: bool = False
    lost: bool = False


class Users:
    """The users one bridge reports. `make_recognizer()` gives a fresh recogniser per user."""

    def __init__(self, make_recognizer: Callable[[], object], lost_timeout_s: float, mirrored: bool,
                 reach_mm: float) -> None:
        self.make_recognizer = make_recognizer
        self.lost_timeout_s, self.mirrored, self.reach_mm = lost_timeout_s, mirrored, reach_mm
        self._users: dict[int, _User] = {}
        #: seconds spent in the recognisers since the last `report()` (the bench reads it)
        self.recognising = 0.0

    def __len__(self) -> int:
        """How many users are known (reported or about to be)."""
        return len(self._users)

    def _get(self, user: int, now: float) -> _User:
        u = self._users.get(user)
        if u is None or u.lost:
            u = self._users[user] = _User(user, self.make_recognizer(), now)
        u.last_seen = now
        return u

    def announce(self, user: int, now: float) -> None:
        """The bridge says this user is new (no body yet)."""
        self._get(user, now)

    def leave(self, user: int, t: float) -> list[Gesture]:
        """The bridge says this user left: LOST in the next frame; strokes under way are judged."""
        u = self._users.get(user)
        if u is None or u.lost:
            return []
        u.lost = True
        return self._flush(u, t)

    def sample(self, user: int, joints: Mapping[str, Joint], t: float, now: float) -> list[Gesture]:
        """One bridge frame of a user: its joints at source time `t`; returns the gestures it completes."""
        u = self._get(user, now)
        if u.sample_t is not None and t < u.sample_t:
            t = u.sample_t  # a datagram overtaken on the way: never run the recogniser backwards
        u.joints.update(joints)
        u.sample_t = t
        hands = [h for h in self._hands(u, HandState.TRACKING) if HANDS[h.side][0] in joints]
        body = {name: u.joints[name].position for name in ("torso", "head") if name in u.joints}
        start = time.perf_counter()
        gestures = u.recognizer.update(t, hands, body, self.mirrored)
        self.recognising += time.perf_counter() - start
        return [replace(g, user_id=user) for g in gestures]

    def expire(self, now: float, t: float) -> list[Gesture]:
        """Users whose messages stopped become lost; returns what their recognisers still complete."""
        gestures = []
        for u in self._users.values():
            limit = self.lost_timeout_s if u.joints else CALIBRATING_S
            if not u.lost and now - u.last_seen > limit:
                u.lost = True
                gestures += self._flush(u, max(t, u.sample_t or t))
        return gestures

    def finish(self, t: float) -> list[Gesture]:
        """The stream ended: every user still in view is lost; its recogniser judges what is
        pending as at the end of a clip (GestureRecognizer.finish)."""
        gestures = []
        for u in self._users.values():
            if not u.lost:
                u.lost = True
                gestures += [replace(g, user_id=u.id) for g in u.recognizer.finish()]
        return gestures

    def report(self) -> tuple[tuple[User, ...], tuple[Hand, ...]]:
        """This frame's users and hands; a LOST user is reported once, then forgotten."""
        users, hands = [], []
        for key, u in list(self._users.items()):
            state = HandState.LOST if u.lost else (HandState.TRACKING if u.reported else HandState.NEW)
            if u.lost and not u.reported:
                del self._users[key]  # came and went between two frames: never shown
                continue
            u.reported = True
            users.append(User(u.id, state, dict(u.joints), center_of_mass(u.joints)))
            hands += self._hands(u, state)
            if u.lost:
                del self._users[key]
        return tuple(users), tuple(hands)

    def _flush(self, u: _User, t: float) -> list[Gesture]:
        gone = self._hands(u, HandState.LOST)
        return [replace(g, user_id=u.id) for g in u.recognizer.update(t, gone, {}, self.mirrored)]

    def _hands(self, u: _User, state: HandState) -> list[Hand]:
        torso = u.joints["torso"].position if "torso" in u.joints else None
        out = []
        for side, (joint, _) in HANDS.items():
            j = u.joints.get(joint)
            if j is not None:
                out.append(Hand(hand_id(u.id, side), state, j.position, side, u.id, j.confidence,
                                extended(j.position, torso, self.reach_mm)))
        return out


class BlankDepth:
    """A depth image of no readings (0) with a camera's geometry, for backends that have no depth:
    effects place hands on the stage through a frame's depth intrinsics, so they work unchanged.
    One read-only array is shared by every frame."""

    def __init__(self) -> None:
        self._zeros: np.ndarray | None = None

    def __call__(self, size: tuple[int, int], intrinsics: Intrinsics, frame_id: int, t: float,
                 capture_time: float, mirrored: bool) -> DepthFrame:
        width, height = size
        if self._zeros is None or self._zeros.shape != (height, width):
            self._zeros = np.zeros((height, width), np.uint16)
            self._zeros.flags.writeable = False
        return DepthFrame(self._zeros, intrinsics, frame_id, t, capture_time, mirrored)
