"""Median and percentiles of small 1-D arrays by partial sorting.

numpy's median and percentile are general (axes, NaN checks, several methods); the engine takes
a few dozen of them per user and frame on arrays of a few hundred cells, where that generality
costs more than the selection itself. These give numpy's results exactly (linear method, the
input's dtype, as numpy scalars), for finite values.
"""
from __future__ import annotations

import math

import numpy as np


def median(a: np.ndarray) -> np.floating:
    """np.median of a non-empty 1-D array (the mean of the two middle values when even), in its dtype."""
    n = a.size
    half = n // 2
    part = _partition(a, half)
    if n % 2:
        return part[half]
    return (_below(part, half) + part[half]) / 2


def percentiles(a: np.ndarray, qs: tuple[float, ...]) -> list[np.floating]:
    """np.percentile(a, q) for each q (linear interpolation) of a non-empty 1-D array, one partial sort."""
    n = a.size
    spots = [_spot(n, q) for q in qs]
    part = _partition(a, sorted({i for lo, hi, _ in spots for i in (lo, hi)}))
    return [_between(part[lo], part[hi], gamma) for lo, hi, gamma in spots]


def percentile(a: np.ndarray, q: float) -> np.floating:
    """np.percentile(a, q) of a non-empty 1-D array, in its dtype."""
    lo, hi, gamma = _spot(a.size, q)
    if lo == hi:  # the first or the last value
        value = _partition(a, lo)[lo]
        return _between(value, value, gamma)
    if a.size - hi < lo:  # the two neighbours from one partial sort, then the few values past it
        part = _partition(a, lo)
        return _between(part[lo], part[hi:].min(), gamma)
    part = _partition(a, hi)
    return _between(_below(part, hi), part[hi], gamma)


def _spot(n: int, q: float) -> tuple[int, int, float]:
    """The two sorted positions the q-th percentile of n values lies between, and how far along."""
    virtual = (n - 1) * (q / 100)
    lo = math.floor(virtual)
    return min(max(lo, 0), n - 1), min(max(lo + 1, 0), n - 1), virtual - lo


def _between(below: np.floating, above: np.floating, gamma: float) -> np.floating:
    """numpy's linear interpolation between two sorted neighbours (the same rounding)."""
    diff = above - below
    return above - diff * (1 - gamma) if gamma >= 0.5 else below + diff * gamma


def _below(part: np.ndarray, k: int) -> np.floating:
    """The (k-1)-th smallest value of an array partitioned at k: the largest before it (one partial
    sort at k and a max cost less than a partial sort at both k-1 and k)."""
    return part[:k].max()


def _partition(a: np.ndarray, k: int | list[int]) -> np.ndarray:
    """np.partition(a, k) of a 1-D array (k: one position or several), without np.partition's
    wrapper (a copy partitioned in place)."""
    part = a.copy()
    part.partition(k)
    return part
