"""Nuitrack's hands: a left and a right hand for as long as the user is in view, at rest too.

Nuitrack reports a skeleton's two hands from the moment it finds the user; the open engine finds
only hands that stick out of the body. In Nuitrack mode a side with no hand in view is reported
where a hanging hand is (beside the hip, in front of the torso, in mm, GestureRules' resting-hand
figures) with confidence 0: effects that follow both hands always have two, and can tell a seen
hand from a resting guess. Ids are those the Nuitrack adapter gives (user 1: left 1, right 2;
user n: 2n - 1 and 2n), and gestures name the same ids. When the user is out of view longer than `lost_timeout_s`, both hands
are LOST once; a shorter dropout reports no hands, as the tracker does.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace

from host import Gesture, Hand, HandState, Side, Vec3

SIDE_IDS = {Side.LEFT: 1, Side.RIGHT: 2}


@dataclass
class RestingHands:
    """Per frame: the tracker's hands in, one hand per side out."""

    below_torso_mm: float  # a hanging hand is this far below the torso (spine) joint
    in_front_mm: float  # and this far in front of it
    beside_mm: float  # and this far out from the spine
    lost_timeout_s: float
    user: int = 1
    _last: dict[Side, Hand] = field(default_factory=dict, init=False)  # what was reported last, per side
    _user_seen: float | None = field(default=None, init=False)

    def present(self, t: float, hands: tuple[Hand, ...], body: dict[str, Vec3], mirrored: bool) -> tuple[Hand, ...]:
        torso = body.get("torso")
        if torso is None:
            if self._last and self._user_seen is not None and t - self._user_seen > self.lost_timeout_s:
                lost = tuple(replace(h, state=HandState.LOST, confidence=0.0) for h in self._last.values())
                self._last.clear()
                return lost
            return ()
        self._user_seen = t
        seen = {h.side: h for h in hands if h.in_view}
        out = []
        for side in SIDE_IDS:
            hand_id = self._id(side)
            hand = seen.get(side)
            if hand is not None:
                position, confidence = hand.position, hand.confidence
                state = HandState.TOUCHING_FOV if hand.state is HandState.TOUCHING_FOV else HandState.TRACKING
            else:
                position, confidence, state = self._rest(side, torso, mirrored), 0.0, HandState.TRACKING
            if side not in self._last:
                state = HandState.NEW
            self._last[side] = Hand(hand_id, state, position, side, self.user, confidence)
            out.append(self._last[side])
        return tuple(out)

    def gesture(self, g: Gesture) -> Gesture:
        """The gesture, naming its hand by this side's id."""
        return replace(g, hand_id=self._id(g.side)) if g.side in SIDE_IDS else g

    @property
    def reporting(self) -> bool:
        """Whether hands are out (not yet LOST)."""
        return bool(self._last)

    def _id(self, side: Side) -> int:
        return 2 * (self.user - 1) + SIDE_IDS[side]

    def _rest(self, side: Side, torso: Vec3, mirrored: bool) -> Vec3:
        """Where a hanging hand is: the performer's right is the image's right when mirrored."""
        outwards = 1.0 if (side is Side.RIGHT) == mirrored else -1.0
        x, y, z = torso
        return (x + outwards * self.beside_mm, y - self.below_torso_mm, z - self.in_front_mm)
