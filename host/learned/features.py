"""What a learned gesture is made of: the hands' motion relative to the body, in body units.

Each instant becomes one posture vector: the left hand then the right hand, each as (x, y, z)
relative to the torso, divided by the body's size (the head-torso distance: about 0.5 m for an
adult, so a child's gesture and a tall adult's give the same numbers), with +x towards the
performer's right whichever way the camera mirrors. Postures are resampled to a fixed rate so
that templates and live streams line up whatever the camera's frame rate.

The body points are the performer's own wherever the backend reports users (the open engine,
osc-in, a CSV's torso and head rows), in teaching as in the show (`performer_body`): against the
UTD-MHAD skeleton, the open engine's torso and head put its hands' postures 0.145 body units off
(median) where the estimate below puts them 0.229 off (bench/learned_depth.py). Without body
points (a backend that reports hands only) the torso is estimated from the hands: the place they
last hung at rest, a body size below it. Rest is the lowest the hands have been over the last
_REST_WINDOW_S, not the last few seconds: a performer gesturing on and on with the hands up would
otherwise pull the torso up with them (docs/learned-gestures.md gives the cost).
"""
from __future__ import annotations

import statistics
from collections import deque
from dataclasses import dataclass
from typing import Iterable, Mapping, Sequence

import numpy as np

from host.model import Frame, Hand, Side, User, Vec3

RATE_HZ = 15.0  # postures per second, templates and live streams alike
DEFAULT_SIZE_MM = 520.0  # head-torso distance of an adult, used until a head is seen
HAND_HOLD_S = 0.5  # a hand unseen for longer hangs at rest (a depth engine reports only hands held out)
REST_PLACE = {Side.LEFT: (-0.3, -0.6, -0.25), Side.RIGHT: (0.3, -0.6, -0.25)}  # hands at rest, body units
TICK_SLACK_S = 1e-3  # timestamps are written to the millisecond or finer: a tick this little after a sample falls on it
_SIZE_WINDOW = 60  # head-torso distances in the running median (two seconds at 30 Hz)
_REST_WINDOW_S = 40.0  # without a torso: how far back the hands' resting place is looked for, ...
_REST_SHARE = 5.0  # ... as the lowest this percent of their places (2 s of the 40: a performer rests that long) ...
_REST_LAST_S = 2.0  # ... where they hung there last (its last this many seconds): a performer who walks is followed
_REST_EVERY_S = 0.1  # one hand place kept per this many seconds (400 over the window, whatever the frame rate)
BODY = ("torso", "head")  # the body points postures are measured against


def body_of(user: User) -> dict[str, Vec3]:
    """A user's torso and head, those its skeleton has."""
    return {name: user.joints[name].position for name in BODY if name in user.joints}


def performer_body(frame: Frame) -> dict[str, Vec3]:
    """The body points of the performer whose hands `frame` reports (the first user with one of
    them, else the first user): what a taught take is measured against, as the show measures each
    user's hands against their own. {} for a frame without users: the torso is then estimated."""
    if not frame.users:
        return {}
    owners = {h.user_id for h in frame.hands if h.in_view}
    return body_of(next((u for u in frame.users if u.id in owners), frame.users[0]))


@dataclass
class Posture:
    """One instant: source seconds and the 6-vector (left x, y, z, right x, y, z) in body units."""

    t: float
    vector: np.ndarray


class PostureStream:
    """Fed each frame's hands and body points; yields postures at RATE_HZ.

    Hands are told apart by their side when the backend knows it, else by where they are (the one
    further to the performer's left is the left). A hand unseen for a moment keeps its place; one
    unseen for longer than HAND_HOLD_S hangs at rest (REST_PLACE). With no hand at all the stream
    breaks: no posture until a hand is back."""

    def __init__(self, mirrored: bool = True, rate_hz: float = RATE_HZ) -> None:
        self.flip = 1.0 if mirrored else -1.0  # camera x -> the performer's right
        self.period = 1.0 / rate_hz
        self._next: float | None = None
        self._last: Posture | None = None
        self._hands: dict[Side, tuple[float, np.ndarray]] = {}
        self._sizes: deque[float] = deque(maxlen=_SIZE_WINDOW)
        self._low: deque[tuple[float, np.ndarray]] = deque()  # without a torso: recent hand places
        self._rest: np.ndarray | None = None  # ... and where they rest, read from them when they change
        self.broken = False  # the last update had no posture (a hand gone): matching starts again

    def update(self, t: float, hands: Sequence[Hand], body: Mapping[str, Sequence[float]]) -> list[Posture]:
        self._see(t, hands)
        vector = self._vector(t, body)
        self.broken = vector is None
        if vector is None:
            self._last = None
            self._next = None
            return []
        now = Posture(t, vector)
        out = []
        if self._next is None:
            self._next = t
        while self._next <= t + TICK_SLACK_S:  # linear interpolation between the last frame and this one
            tick = self._next
            if self._last is None or t <= self._last.t:
                out.append(Posture(tick, vector))
            else:
                w = min(1.0, (tick - self._last.t) / (t - self._last.t))
                out.append(Posture(tick, self._last.vector + w * (vector - self._last.vector)))
            self._next += self.period
        self._last = now
        return out

    def _see(self, t: float, hands: Sequence[Hand]) -> None:
        seen = [h for h in hands if h.in_view]
        sides = [h.side for h in seen]
        if len(seen) == 2 and (Side.UNKNOWN in sides or sides[0] == sides[1]):
            seen = sorted(seen, key=lambda h: self.flip * h.position[0])
            sides = [Side.LEFT, Side.RIGHT]
        elif len(seen) == 1 and sides[0] == Side.UNKNOWN:
            sides = [self._nearest_side(np.asarray(seen[0].position, float))]
        for hand, side in zip(seen, sides):
            if side != Side.UNKNOWN:
                self._hands[side] = (t, np.asarray(hand.position, float))

    def _nearest_side(self, position: np.ndarray) -> Side:
        known = [(np.linalg.norm(p - position), s) for s, (_, p) in self._hands.items()]
        return min(known)[1] if known else Side.RIGHT

    def _vector(self, t: float, body: Mapping[str, Sequence[float]]) -> np.ndarray | None:
        seen = {s: h[1] for s, h in self._hands.items() if t - h[0] <= HAND_HOLD_S}
        if not seen:
            return None  # nobody there
        torso, head = body.get("torso"), body.get("head")
        if torso is not None and head is not None:
            size = float(np.linalg.norm(np.subtract(head, torso)))
            if size > 100.0:  # a real head above a real torso; anything else is a glitch
                self._sizes.append(size)
        size = statistics.median(self._sizes) if self._sizes else DEFAULT_SIZE_MM
        centre = np.asarray(torso, float) if torso is not None else self._estimated_torso(t, seen, size)
        rel = []
        for side in (Side.LEFT, Side.RIGHT):
            if side in seen:
                place = (seen[side] - centre) / size
                place[0] *= self.flip
            else:
                place = np.array(REST_PLACE[side])
            rel.append(place)
        return np.concatenate(rel)

    def _estimated_torso(self, t: float, seen: dict[Side, np.ndarray], size: float) -> np.ndarray:
        """No skeleton: the torso below where the hands last hung at rest, rest being their lowest
        places of the window (a hand unseen is taken to hang at rest, where the seen one's partner
        would)."""
        if len(seen) == 2:
            middle = (seen[Side.LEFT] + seen[Side.RIGHT]) / 2
        else:
            side, place = next(iter(seen.items()))
            middle = place - self.flip * np.array([REST_PLACE[side][0] * size, 0.0, 0.0])
        changed = not self._low or t - self._low[-1][0] >= _REST_EVERY_S
        if changed:
            self._low.append((t, middle))
        while t - self._low[0][0] > _REST_WINDOW_S:
            self._low.popleft()
            changed = True
        if changed:  # rest is read again only when the places kept change (every _REST_EVERY_S)
            self._rest = self._rest_place()
        return self._rest - np.array([0.0, REST_PLACE[Side.LEFT][1], REST_PLACE[Side.LEFT][2]]) * size

    def _rest_place(self) -> np.ndarray:
        """Where the hands last hung at rest: the lowest _REST_SHARE percent of the places kept."""
        times = np.array([when for when, _ in self._low])
        places = np.array([place for _, place in self._low])
        if len(places) < 5:
            return places[np.argmin(places[:, 1])]
        low = places[:, 1] <= np.percentile(places[:, 1], _REST_SHARE)
        return places[low & (times >= times[low].max() - _REST_LAST_S)].mean(axis=0)


def resampled(postures: np.ndarray, rate_hz: float) -> np.ndarray:
    """Postures sampled at `rate_hz` -> at RATE_HZ (a file may have been taught at another rate)."""
    if abs(rate_hz - RATE_HZ) < 1e-6:
        return postures
    n = len(postures)
    t_old = np.arange(n) / rate_hz
    t_new = np.arange(0.0, t_old[-1] + 1e-9, 1.0 / RATE_HZ)
    return np.column_stack([np.interp(t_new, t_old, postures[:, c]) for c in range(postures.shape[1])])


def postures(frames: Iterable[tuple[float, Sequence[Hand], Mapping]], mirrored: bool) -> tuple[np.ndarray, np.ndarray]:
    """A whole recording at RATE_HZ: (times (n,), postures (n, 6)). Gaps (a hand gone) are left out."""
    stream = PostureStream(mirrored)
    out = [p for t, hands, body in frames for p in stream.update(t, hands, body)]
    if not out:
        return np.zeros(0), np.zeros((0, 6))
    return np.array([p.t for p in out]), np.array([p.vector for p in out])
