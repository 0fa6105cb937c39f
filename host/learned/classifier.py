"""Which of the loaded learned gestures the last moment looks like: a small classifier that vetoes
the template matcher's confusions.

The template matcher (matcher.py) asks "is this close to a taught repetition?" one gesture at a
time; it cannot tell that a performance is closer to another learned gesture, and its distances
overlap between gestures that share a posture (hands raised to the front for wind_it_up, goggles
and shoot). The classifier answers the other question, "which of these gestures, or none?", from
the shape of the last WINDOW postures (where the hands were, where they are relative to each
other, how they moved). It is trained when the gestures are loaded, from the repetitions stored in
their files: the last (1 - EARLY) of each repetition is that gesture, its beginning, the rest
pose before it and the rest after it are "none", and every other loaded gesture's repetitions are
negatives, as are the counter-examples a file holds (`issv learn --unlike`: motions the artist
says it is not, every moment of them "none"). The files stay as `issv learn` wrote them, and a set
of gestures loaded together is told apart by what it contains; a set's classifier is trained once
and kept in the user's cache (cache.py), as training takes seconds and a set is loaded again and
again.

It must also say "none" to motions it never saw. A linear classifier cannot: hands on the head
(MSRC-12 had_enough) lie beyond hands at the eyes (goggles) along the very direction that tells
goggles from the other gestures, so it called them goggles all the more (71 of 127 had_enough
instances of p04-p10 fired goggles). So each gesture is also trained on its own repetitions moved
up, down, forward and back by more than its teachers vary, and with the hands that much further
apart (`shifted`: arms lifted outstretched fired beat_both in 32 of 101 instances of p04-p10;
with it beat_both fires in 11 windows of other gestures in all), as "none", and the
standardised descriptors get their squares, with which a class can be bounded on both sides of
each direction: a gesture is a region around where it was taught, not a half-space.

Softmax regression (multinomial logistic regression) on the standardised descriptors and their
squares, fitted with a few hundred Adam steps in numpy (bench/learned.py prints how long six
gestures take to train).
"""
from __future__ import annotations

from collections import deque

import numpy as np

WINDOW = 24  # postures looked back (1.6 s at 15 Hz)
LAG_STEP = 3  # one sample of the window every LAG_STEP postures
_HISTORY = WINDOW + 4  # the window, the velocity's two steps back and the smoothing's two
EARLY = 0.5  # the first half of a repetition (and the rest before it) is "none"
AFTER = WINDOW // 3  # ... and so is the rest after it, from this many postures (0.5 s) on
L2 = 10.0  # ridge penalty (summed over samples): chosen leave-one-teacher-out on MSRC-12 p01-p03
STEPS, RATE = 300, 0.05  # Adam steps and learning rate
EVERY = 2  # train on every EVERY-th posture: neighbours look alike, and it halves the time
SHIFT_SPREAD = 4.0  # "none": the repetitions moved this many times the spread of their climaxes ...
SHIFT_MIN = 0.35  # ... and at least this far (body units; goggles to hands on the head: ~0.3 up, ~0.25 back).
# Both chosen leave-one-teacher-out on MSRC-12 p01-p03 with matcher.AGREE and learner.THRESHOLD_FACTOR


def describe(history: np.ndarray) -> np.ndarray:
    """The descriptor of the last posture of `history` (>= _HISTORY postures, (n, 6)): hand
    places, the hand-to-hand vector and velocities at 8 instants of the last WINDOW postures,
    plus per coordinate the spread and the mean speed over the window. Causal: only the past."""
    return _descriptors(np.asarray(history, float)[-_HISTORY:], np.array([_HISTORY - 3]))[0]


def describe_all(postures: np.ndarray) -> np.ndarray:
    """The descriptor at every posture of a sequence (n, 6) -> (n, D), history before it padded
    with its first posture (a repetition starts at rest); what `Describer` gives live."""
    padded = np.concatenate([np.repeat(postures[:1], _HISTORY - 1, axis=0), postures])
    return _descriptors(padded, np.arange(len(postures)) + _HISTORY - 3)


def _descriptors(padded: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """Descriptors ending at smoothed postures `ends` of `padded` (index k: padded[k + 2])."""
    q = (padded[2:] + padded[1:-1] + padded[:-2]) / 3  # a 3-posture moving average ending at each
    at = ends[:, None] - np.arange(0, WINDOW, LAG_STEP)  # (n, lags): the instants sampled
    now, back = q[at], q[at - 2]
    sampled = np.concatenate([now, now[..., :3] - now[..., 3:], 3.0 * (now - back)], axis=2).reshape(len(ends), -1)
    window = q[ends[:, None] - np.arange(WINDOW)]  # (n, WINDOW, 6), the latest first
    return np.concatenate([sampled, window.std(axis=1), np.abs(np.diff(window, axis=1)).mean(axis=1) * 5.0], axis=1)


class Describer:
    """The live side of `describe_all`: fed one posture at a time. With `pace` n, it describes every
    n-th of the last postures: a motion performed n times slower, as if at the taught pace."""

    def __init__(self, pace: int = 1) -> None:
        self.pace = pace
        self._history: deque[np.ndarray] = deque(maxlen=pace * _HISTORY)

    def reset(self) -> None:
        self._history.clear()

    def add(self, posture: np.ndarray) -> None:
        if not self._history:
            self._history.extend([posture] * (self._history.maxlen - 1))
        self._history.append(posture)

    def descriptor(self) -> np.ndarray:
        """The descriptor of the last posture added (`describe`, at this describer's pace)."""
        return describe(np.array(self._history)[::-self.pace][::-1])

    def push(self, posture: np.ndarray) -> np.ndarray:
        self.add(posture)
        return self.descriptor()


class Classifier:
    """Probabilities of each of `n` gestures and of "none" (the last column) for a descriptor."""

    def __init__(self, mean: np.ndarray, scale: np.ndarray, weights: np.ndarray, bias: np.ndarray) -> None:
        self.mean, self.scale, self.weights, self.bias = mean, scale, weights, bias

    def probabilities(self, descriptor: np.ndarray) -> np.ndarray:
        s = _expand((descriptor - self.mean) / self.scale) @ self.weights + self.bias
        e = np.exp(s - s.max(axis=-1, keepdims=True))
        return e / e.sum(axis=-1, keepdims=True)

    @classmethod
    def train(cls, repetitions: list[list[np.ndarray]], unlike: list[list[np.ndarray]] | None = None) -> "Classifier":
        """repetitions[g]: gesture g's repetitions (postures (n, 6) at RATE_HZ); unlike[g]: its
        counter-examples (`issv learn --unlike`), "none" every moment."""
        none = len(repetitions)
        xs, ys = [], []
        for postures in (p for takes in unlike or [] for p in takes):
            xs.append(describe_all(postures)[::EVERY])
            ys.append(np.full(len(xs[-1]), none))
        for g, reps in enumerate(repetitions):
            for postures in reps:
                label = np.full(len(postures), none)
                label[int(EARLY * len(postures)):] = g
                still = np.repeat(postures[:1], WINDOW, axis=0)
                back = describe_all(np.concatenate([postures, np.repeat(postures[-1:], WINDOW, axis=0)]))
                back = back[len(postures) + AFTER::EVERY]  # back at rest a moment after it: over
                xs += [describe_all(postures)[::EVERY], describe_all(still)[::EVERY], back]
                ys += [label[::EVERY], np.full(WINDOW, none)[::EVERY], np.full(len(back), none)]
            for moved in shifted(reps):
                xs.append(moved)
                ys.append(np.full(len(moved), none))
        x, y = np.concatenate(xs), np.concatenate(ys)
        mean, scale = x.mean(axis=0), x.std(axis=0) + 1e-6
        weights, bias = _fit(_expand((x - mean) / scale), y, none + 1)
        return cls(mean, scale, weights, bias)


def _expand(z: np.ndarray) -> np.ndarray:
    """Standardised descriptors and their squares (a class bounded on both sides, see the module doc)."""
    return np.concatenate([z, 0.5 * z ** 2], axis=-1)


def shift_size(reps: list[np.ndarray]) -> float:
    """How far a gesture's repetitions are moved to be "none": SHIFT_SPREAD times how much the places
    of their climaxes (hands highest) vary, at least SHIFT_MIN."""
    tops = np.array([r[np.argmax(r[:, 1] + r[:, 4])] for r in reps])
    spread = float(np.mean(tops.std(axis=0))) if len(tops) > 1 else 0.0
    return max(SHIFT_MIN, SHIFT_SPREAD * spread)


def offsets(size: float) -> list[np.ndarray]:
    """Where `shifted` moves a gesture (left x y z, right x y z): both hands together up, down,
    forward and back, and the hands `size` further apart each (arms held out wide)."""
    out = []
    for axis in (1, 2):
        for sign in (-1.0, 1.0):
            offset = np.zeros(6)
            offset[[axis, axis + 3]] = sign * size
            out.append(offset)
    return out + [np.array([-size, 0.0, 0.0, size, 0.0, 0.0])]


def shifted(reps: list[np.ndarray]) -> list[np.ndarray]:
    """Descriptors of the gesture's repetitions (their second half: where the gesture is told) moved
    by `offsets` of `shift_size`: the same motion elsewhere."""
    moves, out = offsets(shift_size(reps)), []
    for postures in reps:
        for offset in moves:
            out.append(describe_all(postures + offset)[int(EARLY * len(postures))::EVERY * 2])
    return out


def _fit(z: np.ndarray, y: np.ndarray, classes: int) -> tuple[np.ndarray, np.ndarray]:
    """Class-balanced softmax regression with an L2 penalty, by Adam on the whole batch."""
    n, d = z.shape
    target = np.eye(classes)[y]
    counts = np.bincount(y, minlength=classes).astype(float)
    weight = (n / (classes * np.maximum(counts, 1)))[y][:, None] / n  # each class counts alike
    params = np.zeros((d + 1, classes), np.float32)
    zb = np.hstack([z, np.ones((n, 1))]).astype(np.float32)
    target, weight = target.astype(np.float32), weight.astype(np.float32)
    m, v = np.zeros_like(params), np.zeros_like(params)
    for step in range(1, STEPS + 1):
        s = zb @ params
        e = np.exp(s - s.max(axis=1, keepdims=True))
        grad = zb.T @ ((e / e.sum(axis=1, keepdims=True) - target) * weight)
        grad[:-1] += 2 * L2 * params[:-1] / n
        m = 0.9 * m + 0.1 * grad
        v = 0.999 * v + 0.001 * grad ** 2
        params -= RATE * (m / (1 - 0.9 ** step)) / (np.sqrt(v / (1 - 0.999 ** step)) + 1e-8)
    return params[:-1].astype(float), params[-1].astype(float)
