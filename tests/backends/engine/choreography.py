"""Synthetic hand trajectories from physical descriptions, for testing the gesture recogniser.

A performer stands (or walks) with the torso at `torso`; each hand moves through key poses
given relative to the torso in millimetres (performer facing the camera, camera coordinates:
x towards the image's right, y up, z away), with minimum-jerk motion between them, the way
human reaching movements are shaped. Sampled at 30 Hz like a Kinect.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from host import Hand, HandState, Side

FPS = 30.0
HEAD_ABOVE_TORSO = 520.0
REST = {Side.LEFT: (-200.0, -330.0, -80.0), Side.RIGHT: (200.0, -330.0, -80.0)}  # hands hanging (mirrored view)
IDS = {Side.LEFT: 1, Side.RIGHT: 2}


def min_jerk(s: np.ndarray) -> np.ndarray:
    """Position fraction along a minimum-jerk reach at time fraction s in [0, 1]."""
    s = np.clip(s, 0.0, 1.0)
    return 10 * s**3 - 15 * s**4 + 6 * s**5


@dataclass
class Path3:
    """Key poses (time s, position mm relative to the torso), min-jerk between them, held after."""

    keys: list[tuple[float, tuple[float, float, float]]]

    def __call__(self, t: float) -> np.ndarray:
        keys = self.keys
        if t <= keys[0][0]:
            return np.array(keys[0][1], float)
        for (t0, p0), (t1, p1) in zip(keys, keys[1:]):
            if t <= t1:
                f = float(min_jerk(np.array((t - t0) / (t1 - t0))))
                return np.array(p0, float) + f * (np.array(p1, float) - np.array(p0, float))
        return np.array(keys[-1][1], float)

    def then(self, duration: float, to: tuple[float, float, float]) -> "Path3":
        """Move to `to` (relative to the torso) in `duration` seconds after the last key."""
        return Path3(self.keys + [(self.keys[-1][0] + duration, to)])

    def hold(self, duration: float) -> "Path3":
        return self.then(duration, self.keys[-1][1])

    @property
    def end(self) -> float:
        return self.keys[-1][0]


def rest(side: Side, t: float = 0.0) -> Path3:
    return Path3([(t, REST[side])])


@dataclass
class Performance:
    """Hands (by side) and the torso's path in world mm, sampled into frames."""

    hands: dict[Side, Callable[[float], np.ndarray]]
    duration: float
    torso: Callable[[float], np.ndarray] = field(default=lambda t: np.array([0.0, 0.0, 2500.0]))
    mirrored: bool = True
    lean: float | Callable[[float], float] = 0.0  # degrees the body leans to the side (or at time t)
    size: float = 1.0  # the performer's size relative to an adult's: hands and head scaled about the torso

    def frames(self, with_body: bool = True, noise_mm: float = 0.0, seed: int = 0):
        """(t, hands, body) per frame; hand positions are world mm (torso + relative pose)."""
        rng = np.random.default_rng(seed)
        sign = 1.0 if self.mirrored else -1.0  # unmirrored: the performer's right is the image's left
        for i in range(int(round(self.duration * FPS)) + 1):
            t = i / FPS
            torso = self.torso(t)
            hands = []
            for side, path in self.hands.items():
                rel = self.size * path(t) * np.array([sign, 1.0, 1.0])
                p = torso + rel + rng.normal(0.0, noise_mm, 3)
                hands.append(Hand(IDS[side], HandState.TRACKING, tuple(float(c) for c in p), side))
            lean = np.radians(self.lean(t) if callable(self.lean) else self.lean)
            up = np.array([np.sin(lean), np.cos(lean), 0.0])
            body = {"torso": tuple(torso), "head": tuple(torso + self.size * HEAD_ABOVE_TORSO * up)}
            yield t, hands, (body if with_body else {})

    def write_csv(self, path: Path, with_body: bool = True) -> Path:
        """The performance as a hand-trajectory CSV (docs/architecture.md)."""
        lines = ["t,hand,x,y,z"]
        for t, hands, body in self.frames(with_body):
            for h in hands:
                lines.append(f"{t:.4f},{h.side.value},{h.position[0]:.1f},{h.position[1]:.1f},{h.position[2]:.1f}")
            for name, p in body.items():
                lines.append(f"{t:.4f},{name},{p[0]:.1f},{p[1]:.1f},{p[2]:.1f}")
        path.write_text("\n".join(lines) + "\n")
        return path


# --- the choreographies (positions relative to the torso, mirrored view: +x = performer's right) ---

RAISED = (250.0, 350.0, -400.0)  # right hand up in front of the shoulder


def swipe(travel: float = 500.0, duration: float = 0.5, to_right: bool = False, other_along: float = 0.0) -> Performance:
    """The right hand rises, sweeps `travel` mm sideways in `duration` s, holds, drops back. With
    `other_along`, the left hand, held up in front of the body, sweeps that share of the travel the same
    way at the same time (the arms swinging together as the body turns, balancing a kick)."""
    x0 = RAISED[0] if not to_right else RAISED[0] - travel
    start = (x0, RAISED[1], RAISED[2])
    end = (x0 - travel if not to_right else x0 + travel, RAISED[1], RAISED[2])
    right = rest(Side.RIGHT).hold(0.3).then(0.6, start).hold(0.3).then(duration, end).hold(0.4).then(0.8, REST[Side.RIGHT])
    left = rest(Side.LEFT)
    if other_along:
        along = (end[0] - start[0]) * other_along
        held = (-250.0, 150.0, -300.0)
        left = (left.hold(0.3).then(0.6, held).hold(0.3).then(duration, (held[0] + along, held[1], held[2]))
                .hold(0.4).then(0.8, REST[Side.LEFT]))
    return Performance({Side.LEFT: left, Side.RIGHT: right}, right.end + 0.5)


def swipe_up(travel: float = 550.0, duration: float = 0.4) -> Performance:
    """The right hand, up in front of the belly, sweeps `travel` mm straight up in front of the chest."""
    low = (250.0, -50.0, -400.0)
    right = (rest(Side.RIGHT).hold(0.3).then(0.6, low).hold(0.3).then(duration, (low[0], low[1] + travel, low[2]))
             .hold(0.4).then(0.8, REST[Side.RIGHT]))
    return Performance({Side.LEFT: rest(Side.LEFT), Side.RIGHT: right}, right.end + 0.5)


def swept_up_overhead(top: float = 330.0, up_s: float = 0.4, aside: float = 400.0, aside_s: float = 0.6,
                      hold: float = 0.1) -> Performance:
    """The right hand, up in front of the belly, sweeps straight up to `top` mm above the head's
    centre in `up_s` s and, before it has stopped, on out to the side by `aside` mm in `aside_s` s
    (an arm lifted and opened in one motion), held there `hold` s and lowered to rest in 0.8 s."""
    low = np.array([250.0, -50.0, -400.0])
    start = 0.3 + 0.6 + 0.3
    opened = start + 0.6 * up_s + aside_s
    top_place = low + np.array([aside, HEAD_ABOVE_TORSO + top - low[1], 0.0])
    rise = rest(Side.RIGHT).hold(0.3).then(0.6, tuple(low))
    lower = Path3([(opened, tuple(top_place))]).hold(hold).then(0.8, REST[Side.RIGHT])

    def right(t: float) -> np.ndarray:
        if t <= start:
            return rise(t)
        if t >= opened:
            return lower(t)
        up = float(min_jerk(np.array((t - start) / up_s)))
        out = float(min_jerk(np.array((t - start - 0.6 * up_s) / aside_s)))
        return low + np.array([aside * out, (top_place[1] - low[1]) * up, 0.0])
    return Performance({Side.LEFT: rest(Side.LEFT), Side.RIGHT: right}, lower.end + 0.5)


def windup_swipe(windup: float = 250.0, start: tuple[float, float, float] = (150.0, 350.0, -400.0),
                 still: float = 0.2, windup_s: float = 0.35, to: float = -250.0) -> Performance:
    """The right hand, raised to `start` and held `still` s, winds up `windup` mm out to the performer's
    right in `windup_s` s, then turns straight into a swipe to the left, across the body to `to`."""
    out = (start[0] + windup, start[1], start[2])
    right = (rest(Side.RIGHT).hold(0.3).then(0.6, start).hold(still).then(windup_s, out)
             .then(0.45, (to, start[1], start[2])).hold(0.4).then(0.8, REST[Side.RIGHT]))
    return Performance({Side.LEFT: rest(Side.LEFT), Side.RIGHT: right}, right.end + 0.5)


def rise_across(to: tuple[float, float, float] = (-220.0, 150.0, -420.0), seconds: float = 0.45,
                back: float | None = None, pause: float = 0.1, back_s: float = 0.35,
                lift: float | None = None) -> Performance:
    """The right hand, hanging still at its side, rises across the body in one diagonal to `to` (a swipe
    to the left across an imaginary screen, as Kinder-Gator's child p106 swipes), holds, drops
    back; or, `back` given, after `pause` s sweeps back flat to x = `back` in `back_s` s (a rise that
    winds up a swipe back, as MSRC-12's push right and UTD-MHAD's subject 4 do). With `lift`, the hand
    first lifts at its side to that height (in 0.2 s, a little forward), then sweeps across."""
    right = rest(Side.RIGHT).hold(1.0)
    if lift is not None:
        hanging = REST[Side.RIGHT]
        right = right.then(0.2, (hanging[0] - 20.0, lift, hanging[2] - 40.0))
    right = right.then(seconds, to)
    if back is not None:
        right = right.hold(pause).then(back_s, (back, to[1], to[2]))
    right = right.hold(0.5).then(0.8, REST[Side.RIGHT])
    return Performance({Side.LEFT: rest(Side.LEFT), Side.RIGHT: right}, right.end + 0.5)


def low_sweep(outwards: bool = True, height: float = -230.0, travel: float = 550.0, duration: float = 0.5) -> Performance:
    """The right hand sweeps sideways at waist height (`height` mm below the torso), outwards to end
    far out on the performer's right, or inwards across the body (an arm balancing a kick)."""
    inner, outer = (-100.0, height, -250.0), (-100.0 + travel, height, -250.0)
    start, end = (inner, outer) if outwards else (outer, inner)
    right = rest(Side.RIGHT).hold(0.3).then(0.5, start).hold(0.3).then(duration, end).hold(0.4).then(0.6, REST[Side.RIGHT])
    return Performance({Side.LEFT: rest(Side.LEFT), Side.RIGHT: right}, right.end + 0.5)


def push_out(travel: float = 500.0, duration: float = 0.5, windup: float = 0.0,
             back_after: float | None = None, back_s: float = 0.4) -> Performance:
    """MSRC-12's "push right": the right hand, held in front of the chest, pushed out sideways
    `travel` mm in `duration` s to the performer's right (arm held out), held, dropped; after a
    `windup` mm swing across the body first, if any; brought straight back in front of the chest
    in `back_s` s, `back_after` s after it got there, if given."""
    held = (150.0, 250.0, -350.0)
    out = (held[0] + travel, held[1], held[2])
    right = rest(Side.RIGHT).hold(0.3).then(0.6, held).hold(0.4)
    if windup:
        right = right.then(0.3, (held[0] - windup, held[1], held[2]))
    right = right.then(duration, out)
    if back_after is not None:
        right = right.hold(back_after).then(back_s, held)
    right = right.hold(0.5).then(0.8, REST[Side.RIGHT])
    return Performance({Side.LEFT: rest(Side.LEFT), Side.RIGHT: right}, right.end + 0.5)


def pushes_with_returns(times: int = 3, inner: float = -100.0, outer: float = 550.0, out_s: float = 0.4,
                        hold: float = 0.5, back_s: float = 0.9) -> Performance:
    """MSRC-12's "push right" repeated: the right hand, up in front of the body at `inner`, pushed out to
    `outer` in `out_s` s, held there `hold` s, brought back across in `back_s` s and turned straight
    into the next push, `times` times."""
    a, b = (inner, 100.0, -350.0), (outer, 100.0, -350.0)
    right = rest(Side.RIGHT).hold(0.3).then(0.6, a).hold(0.5)
    for i in range(times):
        right = right.then(out_s, b).hold(hold)
        if i < times - 1:
            right = right.then(back_s, a)
    right = right.hold(0.4).then(0.8, REST[Side.RIGHT])
    return Performance({Side.LEFT: rest(Side.LEFT), Side.RIGHT: right}, right.end + 0.5)


def jittered(performance: Performance, side: Side, at: float, jump: tuple[float, float, float], frames: int = 1) -> Performance:
    """The same performance with the tracker's jitter: `side`'s hand reported `jump` mm off for
    `frames` frames from `at` seconds (a skeleton tracker's glitch during fast motion)."""
    path = performance.hands[side]

    def glitched(t: float) -> np.ndarray:
        return path(t) + (np.array(jump) if at <= t < at + frames / FPS else 0.0)

    return Performance({**performance.hands, side: glitched}, performance.duration, performance.torso,
                       performance.mirrored)


def sweeps(times: int = 4, travel: float = 600.0, seconds: float = 0.7) -> Performance:
    """The right hand sweeps left and right `times` times at chest height without pausing, each
    sweep `travel` mm in `seconds` (slower than any wave's swing): swiping back and forth."""
    left, right_ = (RAISED[0] - travel, RAISED[1], RAISED[2]), RAISED
    right = rest(Side.RIGHT).hold(0.3).then(0.6, RAISED).hold(0.3)
    for i in range(times):
        right = right.then(seconds, left if i % 2 == 0 else right_)
    right = right.hold(0.4).then(0.8, REST[Side.RIGHT])
    return Performance({Side.LEFT: rest(Side.LEFT), Side.RIGHT: right}, right.end + 0.5)


def wave(swings: int = 6, amplitude: float = 240.0, half_period: float | tuple[float, ...] = 0.2,
         height: float = 450.0, rise_s: float = 0.6, pause: float = 0.0, fall_aside: float | None = None) -> Performance:
    """The right hand raised beside the head in `rise_s`, swinging side to side `swings` times, each
    swing lasting `half_period` (or the swings lasting the durations given, one each) and followed by
    a `pause`; then held a moment and brought down to rest, or let fall straight from the last swing,
    down to hang in 0.6 s, swinging `fall_aside` mm sideways on the way (in its first 0.3 s)."""
    durations = half_period if isinstance(half_period, tuple) else (half_period,) * swings
    centre = (250.0, height, -350.0)
    right = rest(Side.RIGHT).hold(0.3).then(rise_s, (centre[0] + amplitude / 2, height, centre[2]))
    for i, duration in enumerate(durations):
        x = centre[0] + (amplitude / 2 if i % 2 else -amplitude / 2)
        right = right.then(duration, (x, height, centre[2]))
        if pause:
            right = right.hold(pause)
    if fall_aside is None:
        right = right.hold(0.2).then(0.8, REST[Side.RIGHT])
        return Performance({Side.LEFT: rest(Side.LEFT), Side.RIGHT: right}, right.end + 0.5)
    last = right.keys[-1][1]
    down = right.then(0.6, (last[0], *REST[Side.RIGHT][1:]))
    aside = right.then(0.3, (last[0] + fall_aside, *last[1:]))

    def falling(t: float) -> np.ndarray:
        return np.array([aside(t)[0], *down(t)[1:]])
    return Performance({Side.LEFT: rest(Side.LEFT), Side.RIGHT: falling}, down.end + 0.5)


def whole_arm_wave(swings: int = 3, opening: tuple[float, float, float] = (450.0, -120.0, -300.0),
                   sag: float = 0.0, half_period: float = 0.25) -> Performance:
    """The right arm lifted out to the side to `opening` in 0.3 s, swung up across the body (sagging by
    `sag` mm halfway: sweeping low across the front rather than rising) and then side to side over the
    shoulder `swings` more times, held out at the side a moment and dropped."""
    left_, right_ = (-200.0, 450.0, -350.0), (450.0, 420.0, -350.0)
    right = rest(Side.RIGHT).hold(0.3).then(0.3, opening)
    across = (right.end, right.end + half_period)
    right = right.then(half_period, left_)
    for i in range(swings):
        right = right.then(half_period, right_ if i % 2 == 0 else left_)
    right = right.hold(0.4).then(0.6, REST[Side.RIGHT])

    def arm(t: float) -> np.ndarray:
        f = np.clip((t - across[0]) / (across[1] - across[0]), 0.0, 1.0)
        return right(t) - np.array([0.0, sag * np.sin(np.pi * f), 0.0])
    return Performance({Side.LEFT: rest(Side.LEFT), Side.RIGHT: arm}, right.end + 0.5)


def swung(path: Callable[[float], tuple[float, float, float]], seconds: float = 0.45) -> Performance:
    """The right hand held at `path(0)`, then along `path(f)` (f the min-jerk fraction of the way) to
    `path(1)` in `seconds`, and held there; the left hand at rest."""
    def right(t: float) -> np.ndarray:
        return np.array(path(float(min_jerk(np.array((t - 0.5) / seconds)))), float)
    return Performance({Side.LEFT: rest(Side.LEFT), Side.RIGHT: right}, 0.5 + seconds + 1.0)


def about_the_shoulder(to_deg: float, drop: float = 0.0) -> Callable[[float], tuple[float, float, float]]:
    """The straight arm swung about its shoulder (200 mm right of the spine, at arm's length, 600 mm) from
    straight ahead to `to_deg` at the fraction f of the way, the hand falling `drop` mm meanwhile."""
    def at(f: float) -> tuple[float, float, float]:
        a = np.radians(to_deg * f)
        return (200.0 + 600.0 * np.sin(a), 150.0 - drop * f, -600.0 * np.cos(a))
    return at


def push(pushes: int = 1, travel: float = 400.0, pause: float = 0.4, seconds: float = 0.25) -> Performance:
    """Both hands up in front of the shoulders, pushed forward `travel` mm in `seconds` and back."""
    hands = {}
    for side, x in ((Side.LEFT, -150.0), (Side.RIGHT, 150.0)):
        near, far = (x, 300.0, -200.0), (x, 300.0, -200.0 - travel)
        path = rest(side).hold(0.3).then(0.6, near).hold(0.3)
        for _ in range(pushes):
            path = path.then(seconds, far).hold(0.15).then(0.3, near).hold(pause)
        hands[side] = path.then(0.7, REST[side])
    end = max(p.end for p in hands.values())
    return Performance(hands, end + 0.5)


def hand_raise(above_head: float = 150.0, hold: float = 1.0, move: float = 0.8, aside: float = 200.0,
               forward: float = 150.0) -> Performance:
    """The right hand lifted in `move` s to `above_head` mm above the head's centre, `aside` mm to its
    side and `forward` mm in front of it, held `hold` s."""
    right = (rest(Side.RIGHT).hold(0.3).then(move, (aside, HEAD_ABOVE_TORSO + above_head, -forward))
             .hold(hold).then(move, REST[Side.RIGHT]))
    return Performance({Side.LEFT: rest(Side.LEFT), Side.RIGHT: right}, right.end + 0.5)


def walk(distance: float = 2000.0, duration: float = 2.5, swing: float = 250.0) -> Performance:
    """Walking `distance` mm across the stage, arms swinging `swing` mm forward and back at 1 Hz."""
    def torso(t: float) -> np.ndarray:
        return np.array([-distance / 2 + distance * float(min_jerk(np.array(t / duration))), 0.0, 2500.0])

    def arm(side: Side) -> Callable[[float], np.ndarray]:
        phase = 0.0 if side is Side.LEFT else np.pi

        def at(t: float) -> np.ndarray:
            swinging = min(1.0, t / 0.5) * min(1.0, max(0.0, (duration + 0.3 - t) / 0.5))
            s = np.sin(2 * np.pi * t + phase) * swinging
            return np.array(REST[side]) + np.array([0.0, 40.0 * abs(s), -swing / 2 * s])
        return at

    return Performance({Side.LEFT: arm(Side.LEFT), Side.RIGHT: arm(Side.RIGHT)}, duration + 0.8, torso)


def clap(claps: int = 4, apart: float = 600.0, beat: float = 0.25) -> Performance:
    """Both hands up at shoulder height, `apart` mm apart, brought together `claps` times."""
    hands = {}
    for side, sign in ((Side.LEFT, -1.0), (Side.RIGHT, 1.0)):
        wide, together = (sign * apart / 2, 300.0, -300.0), (sign * 30.0, 300.0, -300.0)
        path = rest(side).hold(0.3).then(0.5, wide)
        for _ in range(claps):
            path = path.then(beat, together).then(beat, wide)
        hands[side] = path.then(0.6, REST[side])
    return Performance(hands, max(p.end for p in hands.values()) + 0.5)


def hands_at_the_eyes(jiggle: float = 60.0, beat: float = 0.15, times: int = 8) -> Performance:
    """Both hands brought up to the eyes (MSRC-12's "goggles"), jiggling `jiggle` mm sideways together."""
    hands = {}
    for side, sign in ((Side.LEFT, -1.0), (Side.RIGHT, 1.0)):
        eye = (sign * 70.0, 500.0, -150.0)
        path = rest(side).hold(0.3).then(0.6, eye)
        for i in range(times):
            path = path.then(beat, (eye[0] + (jiggle if i % 2 == 0 else 0.0), eye[1], eye[2]))
        hands[side] = path.hold(0.2).then(0.6, REST[side])
    return Performance(hands, max(p.end for p in hands.values()) + 0.5)


def rise_forward(to: tuple[float, float, float], seconds: float = 0.5, both: bool = False,
                 sink: float = 0.0) -> Performance:
    """From hanging at the side, the right hand (or both, mirrored) arcs up and forward to `to`, holds;
    meanwhile the body sinks `sink` mm (a squat) over twice as long."""
    hands = {}
    for side, sign in ((Side.LEFT, -1.0), (Side.RIGHT, 1.0)):
        if side is Side.LEFT and not both:
            hands[side] = rest(side)
            continue
        hands[side] = rest(side).hold(0.4).then(seconds, (sign * to[0], to[1], to[2])).hold(0.8)
    torso = Path3([(0.0, (0.0, 0.0, 2500.0))]).hold(0.4).then(2 * seconds, (0.0, -sink, 2500.0))
    return Performance(hands, max(getattr(p, "end", 0.0) for p in hands.values()) + 0.5, torso)


def rise_into_push(top: float = 400.0, rise_s: float = 0.4, lift_forward: float = 150.0,
                   push: float = 220.0, push_after: float = 0.3, push_s: float = 0.3) -> Performance:
    """From hanging at the side, the right hand rises `top` mm high (relative to the torso) in `rise_s`,
    coming `lift_forward` mm forward as it does, and `push_after` s into the rise, without a stop, pushes
    `push` mm further forward in `push_s` (UTD-MHAD's subject 3 pushes so)."""
    r = np.array(REST[Side.RIGHT])

    def at(t: float) -> np.ndarray:
        rise = float(min_jerk(np.array((t - 0.4) / rise_s)))
        forward = float(min_jerk(np.array((t - 0.4 - push_after) / push_s)))
        return r + np.array([0.0, (top - r[1]) * rise, -lift_forward * rise - push * forward])

    return Performance({Side.LEFT: rest(Side.LEFT), Side.RIGHT: at}, 0.4 + push_after + push_s + 1.0)


def run_in_place(seconds: float = 3.0, swing: float = 450.0, period: float = 0.6) -> Performance:
    """Running on the spot: the arms pump forward and up, back and down, in turn, `period` s a cycle."""
    def arm(side: Side) -> Callable[[float], np.ndarray]:
        phase = 0.0 if side is Side.LEFT else np.pi

        def at(t: float) -> np.ndarray:
            s = np.sin(2 * np.pi * t / period + phase) * min(1.0, t / 0.3)
            return np.array(REST[side]) + np.array([0.0, 230.0 * (1 + s), -swing / 2 * (1 + s)])
        return at

    return Performance({Side.LEFT: arm(Side.LEFT), Side.RIGHT: arm(Side.RIGHT)}, seconds)
