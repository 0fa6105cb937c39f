"""`truth`: a source's ground truth passed through as hands, gestures and users.

The camera-less null tracker of the original framework: effects can be tested deterministically
against exactly what the synthetic performer did. Never a show default. Hands and gestures are
the first performer's (`Truth.hands`, `Truth.gestures`); every performer the truth lists is a
user (NEW when it comes into view, TRACKING, LOST once when it leaves), and the truth's label
image, when the source has one, is the frame's `user_labels`.
"""
from __future__ import annotations

from dataclasses import replace

from host import (Backend, DepthFrame, Frame, Gesture, GestureState, GestureType, Hand, HandState, Joint,
                  Side, Truth, TruthGesture, User, Vec3)
from backends.users import center_of_mass


class TruthBackend(Backend):
    name = "truth"

    def init(self) -> None:
        super().init()
        self._seq = 0
        self._active: set[TruthGesture] = set()
        self._hand_ids: dict[Side, int] = {}
        self._last: DepthFrame | None = None
        self._present: dict[int, User] = {}

    def update(self) -> Frame | None:
        depth = self.source.read()
        if depth is None:
            return self._flush()
        self._last = depth
        truth = depth.truth
        hands: list[Hand] = []
        gestures: list[Gesture] = []
        users: tuple[User, ...] = ()
        if truth is not None and self.tracking_hands:
            owner = truth.users[0].id if truth.users else 1
            for side, position in truth.hands.items():
                new = side not in self._hand_ids
                hand_id = self._hand_ids.setdefault(side, len(self._hand_ids) + 1)
                hands.append(Hand(hand_id, HandState.NEW if new else HandState.TRACKING, position, side, owner))
            users = self._users(truth)
        if truth is not None and self.detecting_gestures:
            gestures = self._gestures(set(truth.gestures), truth.hands, depth.timestamp)
        labels = truth.user_labels if truth is not None else None
        return self._frame(depth, hands, gestures, users, None if labels is None else lambda: labels)

    def _frame(self, depth: DepthFrame, hands, gestures, users=(), labels=None) -> Frame:
        self._seq += 1
        return Frame(self._seq, depth.capture_time, depth, tuple(hands), tuple(gestures), self.name,
                     users=users, make_user_labels=labels)

    def _users(self, truth: Truth) -> tuple[User, ...]:
        """The performers in view, NEW the first frame of each visit; one LOST report when one leaves."""
        users = []
        for u in truth.users:
            joints = {name: Joint(p) for name, p in u.body.items()}
            state = HandState.TRACKING if u.id in self._present else HandState.NEW
            users.append(User(u.id, state, joints, center_of_mass(joints)))
        here = {u.id for u in users}
        gone = [replace(u, state=HandState.LOST) for i, u in self._present.items() if i not in here]
        self._present = {u.id: u for u in users}
        return tuple(users + gone)

    def _flush(self) -> Frame | None:
        """At the end of the stream, complete what is still under way, once."""
        if not self._active or self._last is None:
            return None
        hands = self._last.truth.hands if self._last.truth else {}
        return self._frame(self._last, [], self._gestures(set(), hands, self._last.timestamp))

    def _gestures(self, active: set[TruthGesture], hand_positions: dict[Side, Vec3], t: float) -> list[Gesture]:
        """IN_PROGRESS when an interval first shows, COMPLETE on the first frame it is gone."""
        done = sorted(self._active - active, key=lambda g: g.start)
        started = sorted(active - self._active, key=lambda g: g.start)
        self._active = active
        return ([self._event(g, GestureState.COMPLETE, hand_positions, t) for g in done]
                + [self._event(g, GestureState.IN_PROGRESS, hand_positions, t) for g in started])

    def _event(self, g: TruthGesture, state: GestureState, hand_positions: dict[Side, Vec3], t: float) -> Gesture:
        position = hand_positions.get(g.side, (0.0, 0.0, 0.0))
        return Gesture(GestureType.from_canonical(g.name), state, position,
                       self._hand_ids.get(g.side, 0), g.side, 1.0, t)
