"""A gesture its teachers perform as a loop completes only on a motion that loops.

The templates and the classifier (matcher.py, classifier.py) compare where the hands are and which
way they head, instant by instant. Hands going up and down or back and forth in the same place pass
both for a rolling gesture: on MSRC-12, taught by p01-p03, wind_it_up completed in the windows of
77 of the 1467 instances of p04-p10's other gestures (shoot: 59, beat_both: 16), the largest source
of false fires. None of those motions loops; the wind_it_up performances that were found do. The
teachers never make that confusion, so nothing they taught tells the classifier to look for it:
the loop is read from their repetitions instead (bench/learned.py gives the figures).

Loopiness of a hand in a plane: the area its path sweeps round its own centre, over the area of the
ellipse its spread spans (2 pi sd_a sd_b). About 1 for a circle drawn once round, either way round;
near 0 for a line or a path that comes back the way it went. A learned gesture loops in each (hand,
plane) of the hands it uses where its median repetition, over the last WINDOW postures before the
point where it completes, loops at least LOOPS, if the hands go round that loop: in a quarter of the
repetitions at least, a hand comes back round to within the loop's radius of where it was, having
enclosed that much (`closed_loopiness`). An arc is not such a loop: MSRC-12's p01 and p03 bring
their hands up to the eyes for goggles along an arc that sweeps round its centre as much as a loop
does, and p02's goggles, straight up, must still be goggles.

A performance completes a looping gesture only if, in one of those (hand, plane)s, the motion its
best template has matched has gone round a loop (`closed_loopiness`) of at least `loop` (AS_MUCH
unless a profile says otherwise; 0 turns the check off). One hand is enough: a performer rolling one
arm at a time. Gone round, not only swept round: hands on their way up sweep half a loop, and a slow
performer's big circle matched that far completed it before it was drawn (MSRC-12 p06 winds one
circle in 2.5 s, up in front and down at the sides; wind_it_up completed at the top, 2-3 s before
the action point); hands that beat or shoot along an arc do not go round either. On MSRC-12 taught
by p01-p03, against reading how far the hands swept round (`loopiness`, on the last 1.3 s at the
teaching's pace): false fires 0.082 -> 0.073 on p04-p10 and 0.070 -> 0.058 leaving one teacher
out, recall 0.890 and 0.691 -> 0.687 (p06's wind_it_up 0.18 -> 0.27); matcher.AGREE was then
chosen again. The whole motion the template has matched is read (matcher.py, `_matched`), however
slow: a loop that closes at its end is found in it, and a quick performer's rest and next
repetition before it do not close there. Read on the last 1.3 s of the teaching's pace instead, a
performer who taught their own slow rolls (4-7 s, "Teaching more" in docs/learned-gestures.md) was
no longer found (p06 0.50 -> 0.00).

The loop must also face the way the taught loops did: a hand's areas swept in the three planes
(`swept`) are its loop's shadows on them, their direction which way the loop faces, as close to the
teachers' median way as all but TILT_PERCENT of the teachers' own. A hand pushed out to the side and
brought back lower draws a loop lying flat: MSRC-12's push_right, never a roll (the teachers' rolls
face the camera, leaning towards the side). On p04-p10 false fires 0.0825 -> 0.0804, leaving one
teacher out 0.0697 -> 0.0665, recall unchanged in both. But it may face 45 degrees away at least
(TILT_LEAST): a few teachers say little of how everyone else holds a loop, and depth tracking tilts
it (UTD-MHAD circles taught from two subjects; the figures are in docs/learned-gestures.md, "The loop
must face the way the teachers' loops did"). The areas are unsigned: a loop leaning left or right
faces the same way.

A gesture taught with both hands performed with one arm (matcher.py, `forms`) must go round a
loop at least as big (`least`: the length of the areas) as the median taught hand's.
Gestures whose repetitions do not loop (a punch, a beat, goggles) are not checked.
"""
from __future__ import annotations

import copy
from typing import Callable, Sequence

import numpy as np

from host.learned.gesture_file import LearnedGesture

PLANE_NAMES = ("x-y", "y-z", "x-z")  # as the camera sees it, side on, from above
WINDOW = 20  # postures (1.3 s at 15 Hz) of a taught repetition, up to where it completes, read for loops
LOOPS = 0.45  # a (hand, plane) where the median taught repetition loops at least this much is a loop
AS_MUCH = 0.3  # ... in which a performance must loop at least this much (a profile may override it)
MIN_SEEN = 6  # postures: a shorter match is too little of the motion to tell a loop
TILT_PERCENT = 5  # a performance's loop may face as far from the taught loops' way as all but this percent of theirs,
TILT_LEAST = float(np.cos(np.radians(45.0)))  # ... and 45 degrees at least: few teachers say little of everyone
_SMALL = 0.02  # body units squared: a hand still along one axis encloses nothing, not 0/0


def _planes(postures: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each hand's path in each plane about its centre: the planes' first and second axes, (n, 6)
    each, left hand x-y, y-z, x-z then the right's."""
    p = np.asarray(postures, float)
    p = p - p.mean(axis=0)
    return p[:, [0, 1, 0, 3, 4, 3]], p[:, [1, 2, 2, 4, 5, 5]]


def swept(postures: np.ndarray) -> np.ndarray:
    """Postures (n, 6) -> (2, 3): the area each hand's path sweeps round its centre in x-y, y-z and
    x-z (body units squared). A hand's three are its loop's shadows on the three planes: their
    length is how big the loop is, their direction which way it faces."""
    a, b = _planes(postures)
    return 0.5 * np.abs(np.sum(a[:-1] * b[1:] - a[1:] * b[:-1], axis=0)).reshape(2, 3)


def loopiness(postures: np.ndarray) -> np.ndarray:
    """Postures (n, 6) -> (6,): how much the left hand loops in x-y, y-z and x-z, then the right:
    the area its path sweeps round its centre over the area of the ellipse its spread spans."""
    a, b = _planes(postures)
    return swept(postures).ravel() / (2 * np.pi * a.std(axis=0) * b.std(axis=0) + _SMALL)


def _size_and_facing(areas: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per hand, how big its loop is and the unit direction it faces, from its `swept` areas."""
    size = np.linalg.norm(areas, axis=-1)
    return size, areas / (size[..., None] + 1e-12)


def closed_loopiness(postures: np.ndarray) -> np.ndarray:
    """Like `loopiness`, but of the largest loop the hand has gone round and closed at the last
    posture: the path from an earlier posture (at least MIN_SEEN back) that the hand has come back
    to, within the loop's radius (the root of its summed variances), closed by the chord between
    them. 0 where the hand has not come back round."""
    a, b = _planes(postures)
    count = np.arange(len(a), 0, -1.0)[:, None]  # postures from each start to the end

    def from_each_start(values: np.ndarray) -> np.ndarray:  # sums of values[s:] for every start s
        return np.cumsum(values[::-1], axis=0)[::-1]

    along = np.vstack([from_each_start(a[:-1] * b[1:] - a[1:] * b[:-1]), np.zeros((1, 6))])
    area = 0.5 * np.abs(along + a[-1] * b - a * b[-1])
    var_a = np.maximum(from_each_start(a * a) / count - (from_each_start(a) / count) ** 2, 0.0)
    var_b = np.maximum(from_each_start(b * b) / count - (from_each_start(b) / count) ** 2, 0.0)
    back = (count >= MIN_SEEN) & (np.hypot(a[-1] - a, b[-1] - b) <= np.sqrt(var_a + var_b))
    return np.where(back, area / (2 * np.pi * np.sqrt(var_a * var_b) + _SMALL), 0.0).max(axis=0)


class LoopCheck:
    """Per learned gesture, the loops its teachers drew (`taught`, (gestures, 6): the median
    loopiness where it is a loop, else 0), how much a performance must loop there (`need`), which
    way the taught loops face (`faces`) and how far from that a performance's may (`tilt`), and how
    big it must be (`least`)."""

    def __init__(self, gestures: Sequence[LearnedGesture], taught: list[list[np.ndarray]],
                 one_arm: bool = False) -> None:
        """taught[g]: gesture g's repetitions at RATE_HZ (matcher.taught_repetitions); `one_arm`:
        the gestures are two-handed ones performed with one arm (`LearnedGesture.with_one_arm`)."""
        self.taught = np.zeros((len(gestures), 6))
        self.faces = np.zeros((len(gestures), 3))
        self.tilt = np.full(len(gestures), -1.0)
        self.least = np.zeros(len(gestures))
        for g, (gesture, reps) in enumerate(zip(gestures, taught)):
            prefixes = [r[:gesture.completes_at(len(r))] for r in reps]
            median = np.median([loopiness(p[-WINDOW:]) for p in prefixes], axis=0)
            gone_round = np.percentile([closed_loopiness(p[-WINDOW:]) for p in prefixes], 75, axis=0)
            hands = [h for h, side in enumerate(("left", "right")) if gesture.hands in (side, "both")]
            loops = [c for h in hands for c in range(3 * h, 3 * h + 3) if median[c] >= LOOPS]
            if any(gone_round[c] >= LOOPS for c in loops):  # a loop the hands go round, not an arc
                self.taught[g, loops] = median[loops]
                sizes, faces = _size_and_facing(np.array([swept(p)[hands] for p in prefixes]).reshape(-1, 3))
                self.faces[g] = _size_and_facing(np.median(faces, axis=0))[1]
                self.tilt[g] = min(TILT_LEAST, np.percentile(faces @ self.faces[g], TILT_PERCENT))
                if one_arm:
                    self.least[g] = float(np.median(sizes))
        self.need = np.array([AS_MUCH if g.loop is None else g.loop for g in gestures])
        self.checked = (self.taught > 0).any(axis=1) & (self.need > 0)

    def joined(self, other: "LoopCheck") -> "LoopCheck":
        """One check of this one's gestures, then `other`'s (every attribute is per gesture)."""
        out = copy.copy(self)
        for name, rows in vars(self).items():
            setattr(out, name, np.concatenate([rows, getattr(other, name)]))
        return out

    def passes(self, matched: Callable[[int], np.ndarray], among: np.ndarray | None = None) -> np.ndarray:
        """(gestures,) bool: not a looping gesture, or the motion `matched(g)` (postures (n, 6)) that
        gesture g's best template has matched has gone round a loop where its teachers' did, facing
        their way (and, on one arm, as big as a taught hand's). Read only for the gestures `among`
        ((gestures,) bool; all by default): the matcher asks for those that would agree were the loop
        found, so the loop is not measured at every posture for every gesture."""
        out = ~self.checked
        for g in np.flatnonzero(self.checked if among is None else self.checked & among):
            motion = matched(g)
            if len(motion) >= MIN_SEEN:
                gone_round = ((self.taught[g] > 0) & (closed_loopiness(motion) >= self.need[g])).reshape(2, 3)
                if gone_round.any():  # then which way it faces and how big it is
                    size, faces = _size_and_facing(swept(motion))
                    out[g] = bool(np.any(gone_round.any(axis=1) & (faces @ self.faces[g] >= self.tilt[g])
                                         & (size >= self.least[g])))
        return out

    def describe(self, g: int) -> str:
        """Gesture g's loops in words ("left hand x-y 0.75, right hand y-z 0.64"), "" for none."""
        return ", ".join(f"{('left', 'right')[c // 3]} hand {PLANE_NAMES[c % 3]} {self.taught[g, c]:.2f}"
                         for c in np.flatnonzero(self.taught[g] > 0))
