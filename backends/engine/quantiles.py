"""Median and percentiles of small 1-D arrays by partial sorting.

numpy's median and percentile are general (axes, NaN checks, several methods); the engine takes
a few dozen of them per user and frame on arrays of a few hundred cells, where that generality
costs more than the selection itself. These give numpy's results exactly (linear method, the
input's dtype, as numpy scalars), for finite values.
"""
from __future__ import annotations

import numpy as np


def median(a: np.ndarray) -> np.floating:
    """np.median of a non-empty 1-D array (the mean of the two middle values when even), in its dtype."""
    n = a.size
    half = n // 2
    if n % 2:
        return np.partition(a, half)[half]
    part = np.partition(a, (half - 1, half))
    return (part[half - 1] + part[half]) / 2


def percentiles(a: np.ndarray, qs: tuple[float, ...]) -> list[np.floating]:
    """np.percentile(a, q) for each q (linear interpolation) of a non-empty 1-D array, one partial sort."""
    n = a.size
    spots = []
    for q in qs:
        virtual = (n - 1) * (q / 100)
        lo = int(np.floor(virtual))
        spots.append((min(max(lo, 0), n - 1), min(max(lo + 1, 0), n - 1), virtual - lo))
    part = np.partition(a, sorted({i for lo, hi, _ in spots for i in (lo, hi)}))
    out = []
    for lo, hi, gamma in spots:
        below, above = part[lo], part[hi]
        diff = above - below
        out.append(above - diff * (1 - gamma) if gamma >= 0.5 else below + diff * gamma)
    return out


def percentile(a: np.ndarray, q: float) -> np.floating:
    """np.percentile(a, q) of a non-empty 1-D array, in its dtype."""
    return percentiles(a, (q,))[0]
