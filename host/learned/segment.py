"""Finding the repetitions in a take: stretches of motion away from rest, between moments of rest.

The rest pose is where the hands hang lowest (an artist teaching a gesture starts and ends it
there); a repetition is a stretch in which the posture is well away from it (a share of the
take's largest excursion, so a small gesture and a big one are cut alike). Short gaps are
bridged, blips dropped; a stretch far longer than the others (the performer did not quite come
back to rest between two repetitions) is cut at its points nearest to rest. A repetition touching
the start or end of the take is incomplete and left out.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from host.learned.features import RATE_HZ

REST_SHARE = 0.2  # the lowest fifth of the hands' heights is rest
AWAY_SHARE = 0.3  # away from rest: beyond this share of the take's 95th-percentile excursion
AWAY_MIN = 0.2  # ... and at least this far (body units), so stillness jitter is never a gesture
BRIDGE_S = 0.3  # gaps shorter than this inside a repetition are bridged
SHORTEST_S = 0.4  # stretches shorter than this are blips
PAD_S = 0.15  # a repetition starts and ends this much into the rest around it
TOO_LONG = 1.7  # a stretch this many times the typical length holds several repetitions


@dataclass(frozen=True)
class Repetition:
    """One repetition: index range [start, end) into the take's postures and its times (s)."""

    start: int
    end: int
    t0: float
    t1: float

    @property
    def duration(self) -> float:
        return self.t1 - self.t0


def smooth(x: np.ndarray, taps: int = 3) -> np.ndarray:
    """A short moving average along time (edges keep their own values): tracker jitter out."""
    if len(x) < taps:
        return x.copy()
    kernel = np.ones(taps) / taps
    out = x.copy()
    half = taps // 2
    for c in range(x.shape[1]):
        out[half:len(x) - half, c] = np.convolve(x[:, c], kernel, mode="valid")
    return out


def rest_pose(p: np.ndarray) -> np.ndarray:
    """The median posture among the instants when the hands hang lowest."""
    height = (p[:, 1] + p[:, 4]) / 2
    return np.median(p[height <= np.quantile(height, REST_SHARE)], axis=0)


def find_repetitions(t: np.ndarray, p: np.ndarray) -> list[Repetition]:
    """The repetitions in one take (times t (n,), postures p (n, 6) at RATE_HZ)."""
    if len(t) < 3:
        return []
    p = smooth(p)
    away = np.linalg.norm(p - rest_pose(p), axis=1)
    runs = _runs(away > max(AWAY_MIN, AWAY_SHARE * float(np.quantile(away, 0.95))))
    runs = _bridged(runs, int(round(BRIDGE_S * RATE_HZ)))
    runs = [r for r in runs if r[1] - r[0] >= SHORTEST_S * RATE_HZ]
    runs = _split_long(runs, away)
    n = len(t)
    whole = [r for r in runs if r[0] > 0 and r[1] < n]
    pad = int(round(PAD_S * RATE_HZ))
    out = []
    for a, b in (whole or runs):
        a, b = max(0, a - pad), min(n, b + pad)
        out.append(Repetition(a, b, float(t[a]), float(t[b - 1])))
    return out


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(np.int8), [0]])))
    return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2])]


def _bridged(runs: list[tuple[int, int]], gap: int) -> list[tuple[int, int]]:
    out: list[tuple[int, int]] = []
    for a, b in runs:
        if out and a - out[-1][1] < gap:
            out[-1] = (out[-1][0], b)
        else:
            out.append((a, b))
    return out


def _split_long(runs: list[tuple[int, int]], away: np.ndarray) -> list[tuple[int, int]]:
    if len(runs) < 3:
        return runs
    typical = float(np.median([b - a for a, b in runs]))
    out = []
    for a, b in runs:
        parts = int(round((b - a) / typical))
        if (b - a) < TOO_LONG * typical or parts < 2:
            out.append((a, b))
            continue
        cuts = [a]
        for k in range(1, parts):  # the point nearest rest around each k-th share of the stretch
            centre = a + k * (b - a) // parts
            lo, hi = max(cuts[-1] + 1, centre - int(typical // 2)), min(b - 1, centre + int(typical // 2))
            cuts.append(lo + int(np.argmin(away[lo:hi])) if hi > lo else centre)
        cuts.append(b)
        out.extend((c0, c1) for c0, c1 in zip(cuts, cuts[1:]) if c1 - c0 >= SHORTEST_S * RATE_HZ)
    return out
