"""The DigiEVISS model: evidence spheres, hand cursors, grips and semantic links (thesis ch. 4.3.2).

Pure logic in millimetres and source seconds, no drawing, so it is tested without a renderer.
A hand grabs the sphere it is within the radius of when it does the grab gesture, carries it,
and lets go with the release gesture, when it has been out of sight for a moment (the thesis'
only way), or after a hold timeout. Two spheres are linked when one is being carried and they
touch (centre distance <= sum of radii) for `touch_s`, so that a tracker's one-frame jump of the
hand links nothing; a link is a time-successor relation read left to right (the sphere further
left comes first), and links chain into observation sequences.

Hands are named by who holds them (`HandKey`, e.g. "user 1 right hand"), not by a backend's hand
id: a backend that reports resting hands keeps a user's left and right hand apart however their
ids go, so a sphere carried down to the performer's side stays in that hand. A resting hand
carries its sphere but links nothing: walking past spheres with the arm down is not presenting
one to another (the thesis' performer raises the hand to bring them into touch).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

from host import Vec3


class HandKey(NamedTuple):
    """Which hand holds a sphere: user `user`'s `hand` ("left", "right", or "hand 7" when the
    backend cannot tell sides); prints as the log says it, "user 1 right hand"."""

    user: int
    hand: str

    def __str__(self) -> str:
        return f"user {self.user} {self.hand}" + (" hand" if self.hand in ("left", "right") else "")


@dataclass
class Sphere:
    id: str
    data: str
    center: Vec3
    radius: float


@dataclass
class Grip:
    """A hand holding a sphere: the offset from hand to centre is kept so nothing jumps."""

    sphere: Sphere
    offset: Vec3
    since: float
    seen: float


@dataclass
class Scene:
    spheres: list[Sphere]
    planar: bool = True           # measure distances on the screen plane (x, y); z is ignored
    lost_release_s: float = 0.5   # a grip whose hand is unseen this long lets go
    hold_timeout_s: float = 0.0   # a grip lets go after this long (0: never)
    touch_s: float = 0.0          # spheres link once touching this long (a tracker's one-frame jump links none)
    hands: dict[HandKey, Vec3] = field(default_factory=dict)
    resting: set[HandKey] = field(default_factory=set)  # hands at the performer's side this frame
    grips: dict[HandKey, Grip] = field(default_factory=dict)
    sequences: list[list[str]] = field(default_factory=list)
    log: list[str] = field(default_factory=list)  # what happened, one line each, for the console
    touching: dict[tuple[str, str], float] = field(default_factory=dict)  # (carried, other) -> since when

    def distance(self, a: Vec3, b: Vec3) -> float:
        dims = 2 if self.planar else 3
        return math.dist(a[:dims], b[:dims])

    def holder(self, sphere: Sphere) -> HandKey | None:
        return next((h for h, g in self.grips.items() if g.sphere is sphere), None)

    # -- input -----------------------------------------------------------------------------
    def update(self, hands: dict[HandKey, Vec3], t: float, resting: set[HandKey] = frozenset()) -> bool:
        """New hand positions at source time t (`resting`: those of them at the performer's
        side): carry, time out, link. True when links changed."""
        self.hands, self.resting = dict(hands), set(resting)
        for hand, grip in list(self.grips.items()):
            position = hands.get(hand)
            if position is not None:
                grip.seen = t
                grip.sphere.center = tuple(p + o for p, o in zip(position, grip.offset))
            if t - grip.seen > self.lost_release_s:
                self._release(hand, t, "hand out of sight")
            elif self.hold_timeout_s and t - grip.since > self.hold_timeout_s:
                self._release(hand, t, "hold timeout")
        return self._link_touching(t)

    def grab_or_release(self, hand: HandKey, position: Vec3, t: float, grab: bool, release: bool) -> None:
        """A gesture by `hand` at `position`: release what it holds, or grab what it is in."""
        if hand in self.grips:
            if release:
                self._release(hand, t, "release gesture")
            return
        if not grab:
            return
        free = [s for s in self.spheres if self.holder(s) is None]
        inside = [s for s in free if self.distance(position, s.center) <= s.radius]
        if not inside:
            return
        sphere = min(inside, key=lambda s: self.distance(position, s.center))
        offset = tuple(c - p for c, p in zip(sphere.center, position))
        self.grips[hand] = Grip(sphere, offset, t, t)
        self.log.append(f"{t:8.2f}s  {hand} grabbed {sphere.id}")

    def _release(self, hand: HandKey, t: float, why: str) -> None:
        grip = self.grips.pop(hand)
        self.log.append(f"{t:8.2f}s  {hand} released {grip.sphere.id} ({why})")

    # -- links -----------------------------------------------------------------------------
    def linked(self, a: str, b: str) -> bool:
        return any(abs(s.index(a) - s.index(b)) == 1 for s in self.sequences if a in s and b in s)

    def links(self) -> list[tuple[str, str]]:
        return [(s[i], s[i + 1]) for s in self.sequences for i in range(len(s) - 1)]

    def _link_touching(self, t: float) -> bool:
        changed = False
        carried = [g.sphere for hand, g in self.grips.items() if hand not in self.resting]
        touching = {}
        for moving in carried:
            for other in self.spheres:
                if other is moving or self.linked(moving.id, other.id):
                    continue
                if self.distance(moving.center, other.center) > moving.radius + other.radius:
                    continue
                since = touching[moving.id, other.id] = self.touching.get((moving.id, other.id), t)
                if t - since >= self.touch_s:
                    first, second = sorted((moving, other), key=lambda s: s.center[0])
                    if self._chain(first.id, second.id):
                        self.log.append(f"{t:8.2f}s  linked {first.id} -> {second.id}")
                        changed = True
        self.touching = touching
        return changed

    def _chain(self, first: str, second: str) -> bool:
        """Add first -> second to the sequences: a new sequence, or extend or join existing ones
        at their ends. A link that would branch a sequence or close a loop is refused."""
        head = next((s for s in self.sequences if s[-1] == first), None)
        tail = next((s for s in self.sequences if s[0] == second), None)
        inside = {i for s in self.sequences for i in s}
        if head is not None and tail is not None:
            if head is tail:
                return False
            head.extend(tail)
            self.sequences.remove(tail)
        elif head is not None and second not in inside:
            head.append(second)
        elif tail is not None and first not in inside:
            tail.insert(0, first)
        elif first not in inside and second not in inside:
            self.sequences.append([first, second])
        else:
            return False
        return True
