"""How each action moves the body, in physical units, at speed 1.

Hand paths are keyframes in the body frame (right, up, forward; mm, see performer.py) joined by
minimum-jerk segments (Flash & Hogan 1985: the smooth bell-shaped speed profile of human reaching;
peak speed = 1.875 x distance / time). Every gesture starts and ends with the hand at rest, so
the same hand's gesture intervals never touch. Amplitudes and times follow what people do:
a swipe covers ~50 cm in ~0.45 s after a short wind-up the other way, a wave is 4 oscillations at
2.5 Hz of 20 cm peak to peak, a click pushes 30 cm forward and back, a hand raise lifts the palm
above the head. Walking moves the pelvis with a smooth trapezoidal speed profile, turns the body
towards where it goes, swings the legs in step with the distance covered and the arms against
the legs.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from host import Side
from sources.synthetic.performer import Body, sign


def min_jerk(s: float) -> float:
    """Minimum-jerk progress 0 -> 1 for s in [0, 1], zero speed and acceleration at both ends."""
    s = min(max(s, 0.0), 1.0)
    return s * s * s * (10 - 15 * s + 6 * s * s)


@dataclass(frozen=True)
class Track:
    """A hand path: keyframe times (s, ascending) and palm positions (mm, body frame)."""

    times: tuple[float, ...]
    points: tuple[np.ndarray, ...]

    def at(self, t: float) -> np.ndarray:
        if t <= self.times[0]:
            return self.points[0]
        for i in range(1, len(self.times)):
            if t < self.times[i]:
                t0, t1 = self.times[i - 1], self.times[i]
                p0, p1 = self.points[i - 1], self.points[i]
                return p0 + (p1 - p0) * min_jerk((t - t0) / (t1 - t0))
        return self.points[-1]


@dataclass(frozen=True)
class Oscillation:
    """A side-to-side wave over [start, end]: sine in x, the palm dipping on an arc at the ends."""

    start: float
    end: float
    hz: float
    amplitude: float  # mm, half of peak to peak
    outwards: float  # body-frame x of the first swing: +1 or -1
    ramp: float = 0.12  # s to swing up to full amplitude and back down

    def at(self, t: float) -> np.ndarray:
        if not self.start < t < self.end:
            return np.zeros(3)
        envelope = min_jerk((t - self.start) / self.ramp) * min_jerk((self.end - t) / self.ramp)
        swing = np.sin(2 * np.pi * self.hz * (t - self.start))
        return self.amplitude * envelope * np.array([self.outwards * swing, -0.35 * swing * swing, 0.0])


@dataclass(frozen=True)
class HandMotion:
    """One step's movement of its hand and the gesture interval (step seconds), if any."""

    track: Track
    gesture: tuple[float, float] | None
    oscillation: Oscillation | None = None

    @property
    def length(self) -> float:
        """Seconds from leaving rest to being back at rest."""
        return self.track.times[-1]

    def at(self, t: float) -> np.ndarray:
        palm = self.track.at(t)
        return palm + self.oscillation.at(t) if self.oscillation is not None else palm


WAVE_HZ = 2.5
WAVE_CYCLES = 4
WAVE_MIN_CYCLES = 3
WAVE_RAISE = 0.4  # s to lift the hand into the waving position, and to lower it


def hand_motion(action: str, body: Body, side: Side, duration: float | None) -> HandMotion:
    """The movement of `side`'s hand for a one-handed action; `duration` only matters for a wave."""
    return _BUILDERS[action](body, side, duration)


def min_length(action: str) -> float:
    """The shortest duration (s at speed 1) in which a person does this action naturally."""
    if action == "wave":
        return 2 * WAVE_RAISE + WAVE_MIN_CYCLES / WAVE_HZ
    if action in _BUILDERS:
        return _BUILDERS[action](Body(1750.0), Side.RIGHT, None).length
    return WALK_MIN_S if action == "walk" else 0.0


def _path(body: Body, side: Side, keys: list[tuple[float, tuple[float, float, float]]], end: float) -> Track:
    """From rest at 0 s through `keys` back to rest at `end`. Key positions are (out from the body's
    centre on this hand's side, up, forward) in heights, so one table serves either hand."""
    h, s = body.height, sign(side)
    points = [body.rest(side)] + [np.array([s * o * h, u * h, f * h]) for _, (o, u, f) in keys] + [body.rest(side)]
    return Track((0.0, *(t for t, _ in keys), end), tuple(points))


def _wave(body: Body, side: Side, duration: float | None) -> HandMotion:
    cycles = WAVE_CYCLES if duration is None else max(WAVE_MIN_CYCLES, int((duration - 2 * WAVE_RAISE) * WAVE_HZ))
    start, end = WAVE_RAISE, WAVE_RAISE + cycles / WAVE_HZ
    up = (0.16, 0.92, 0.17)  # palm beside the head, forearm up, in front of the shoulder
    track = _path(body, side, [(start, up), (end, up)], end + WAVE_RAISE)
    wave = Oscillation(start, end, WAVE_HZ, 0.057 * body.height, sign(side))
    return HandMotion(track, (start, end), wave)


def _click(body: Body, side: Side, duration: float | None) -> HandMotion:
    ready, pushed = (0.06, 0.74, 0.12), (0.06, 0.74, 0.29)  # 0.17 H = 30 cm forward
    track = _path(body, side, [(0.5, ready), (0.6, ready), (0.9, pushed), (0.98, pushed), (1.28, ready)], 1.78)
    return HandMotion(track, (0.6, 1.28))


def _hand_raise(body: Body, side: Side, duration: float | None) -> HandMotion:
    top = (0.1, 1.12, 0.05)  # arm nearly straight, palm ~20 cm above the top of the head
    track = _path(body, side, [(0.8, top), (2.0, top)], 2.8)
    return HandMotion(track, (0.1, 1.3))


def _swipe_horizontal(towards: float):
    """`towards` +1: to the performer's right. The wind-up goes the other way first."""
    def build(body: Body, side: Side, duration: float | None) -> HandMotion:
        # Positions are "out from centre" for this hand, so a direction in body x becomes side-relative.
        d = towards * sign(side)
        y, f, centre = 0.76, 0.22, 0.06
        track = _path(body, side, [(0.45, (centre - 0.03 * d, y, f)), (0.75, (centre - 0.13 * d, y, f)),
                                   (1.2, (centre + 0.16 * d, y, f)), (1.35, (centre + 0.17 * d, y - 0.02, f - 0.01))],
                      1.85)
        return HandMotion(track, (0.75, 1.2))
    return build


def _swipe_vertical(towards: float):
    """`towards` +1: up. A fast 49 cm stroke between belly and head height."""
    def build(body: Body, side: Side, duration: float | None) -> HandMotion:
        low, high = (0.08, 0.6, 0.2), (0.08, 0.88, 0.2)
        first, last = (low, high) if towards > 0 else (high, low)
        reach = 0.45 if towards > 0 else 0.6  # lifting the hand high first takes longer
        track = _path(body, side, [(reach, first), (reach + 0.1, first), (reach + 0.6, last), (reach + 0.7, last)],
                      reach + 1.3)
        return HandMotion(track, (reach + 0.1, reach + 0.6))
    return build


_BUILDERS = {
    "wave": _wave,
    "click": _click,
    "hand_raise": _hand_raise,
    "swipe_left": _swipe_horizontal(-1.0),
    "swipe_right": _swipe_horizontal(+1.0),
    "swipe_up": _swipe_vertical(+1.0),
    "swipe_down": _swipe_vertical(-1.0),
}
GESTURES = tuple(_BUILDERS)

WALK_MIN_S = 1.0
WALK_RAMP_S = 0.5  # s to reach walking speed, and to stop
WALK_TURN_S = 0.45  # s to turn towards the walking direction, and back to the camera
WALK_MAX_MM_S = 1800.0  # faster is running
STRIDE_HZ = 0.95  # strides (two steps) per second at a normal walk: ~1.1 m strides at 1.1 m/s
MIN_STRIDE_MM = 300.0
ARM_SWING = 0.11  # palm swing forward and back, heights


def walk_length(distance: float) -> float:
    """A natural duration (s at speed 1) to walk `distance` mm, turns included."""
    return max(WALK_MIN_S, WALK_RAMP_S + abs(distance) / 1100.0)


@dataclass(frozen=True)
class Walk:
    """Walking from x0 to x1 (camera mm) in `length` seconds, at constant depth."""

    x0: float
    x1: float
    length: float

    @property
    def in_place(self) -> bool:
        return abs(self.x1 - self.x0) < 50.0

    @property
    def ramp(self) -> float:
        return min(WALK_RAMP_S, self.length / 2)

    @property
    def cruise(self) -> float:
        """Signed walking speed, mm/s: speeding up and slowing down each cost half a ramp."""
        return (self.x1 - self.x0) / (self.length - self.ramp)

    def x(self, t: float) -> float:
        if self.in_place:
            return self.x0 + (self.x1 - self.x0) * min_jerk(t / self.length)
        ramp, t = self.ramp, min(max(t, 0.0), self.length)

        def ramped(q: float) -> float:  # distance covered q s into a smoothstep speed ramp
            r = q / ramp
            return self.cruise * ramp * (r ** 3 - r ** 4 / 2)

        if t < ramp:
            return self.x0 + ramped(t)
        if t > self.length - ramp:
            return self.x1 - ramped(self.length - t)
        return self.x0 + self.cruise * (t - ramp / 2)

    def swing(self, t: float) -> float:
        """0 to 1: how much of a full walking swing the legs and arms have now."""
        return min_jerk(t / self.ramp) * min_jerk((self.length - t) / self.ramp)

    def yaw(self, t: float) -> float:
        """Radians: turn to face the way to go, walk, turn back to the camera."""
        if self.in_place:
            return 0.0
        turn = min(WALK_TURN_S, self.length / 3)
        facing = float(np.copysign(np.pi / 2, self.x1 - self.x0))
        return facing * min_jerk(t / turn) * min_jerk((self.length - t) / turn)

    def phase(self, t: float) -> float:
        """Strides taken: in proportion to the distance covered, so the feet do not slide."""
        if self.in_place:
            return STRIDE_HZ * t
        stride = max(abs(self.cruise) / STRIDE_HZ, MIN_STRIDE_MM)
        return abs(self.x(t) - self.x0) / stride

    def arm(self, body: Body, side: Side, t: float) -> np.ndarray:
        """A hand swinging low beside the hip, forward while the same side's leg goes back."""
        legs = 2 * np.pi * self.phase(t) + (0.0 if side is Side.RIGHT else np.pi)
        swing = -np.sin(legs) * self.swing(t)
        return body.rest(side) + body.height * np.array([0.0, 0.015 * swing * swing, ARM_SWING * swing])
