"""Distances between 3-vectors on Python floats: for one pair, numpy's per-call cost is many times
the arithmetic. The same float as np.linalg.norm(np.subtract(a, b))."""
from __future__ import annotations

import math
from typing import Sequence

import numpy as np


def distance(a: Sequence[float] | np.ndarray, b: Sequence[float] | np.ndarray) -> float:
    """Euclidean distance (mm) between two points given as 3-tuples or arrays of 3."""
    (ax, ay, az), (bx, by, bz) = _floats(a), _floats(b)
    dx, dy, dz = ax - bx, ay - by, az - bz
    return math.sqrt(dx * dx + dy * dy + dz * dz)


def _floats(v: Sequence[float] | np.ndarray) -> Sequence[float]:
    return v.tolist() if isinstance(v, np.ndarray) else v
