"""Matching what was tracked to what is seen now: the assignment with the smallest total cost.

Few things are matched at once (two hands of a user, four people), so every assignment is tried;
a pair outside its gate is not allowed, and leaving one unmatched costs more than any match.
"""
from __future__ import annotations

from itertools import permutations

UNMATCHED = 1e7


def best_assignment(allowed: dict[tuple[int, int], float], tracks: int, found: int) -> list[tuple[int, int]]:
    """(track, found) index pairs of the cheapest assignment, from the allowed pairs' costs."""
    tracks_first = tracks <= found
    small, large = (tracks, found) if tracks_first else (found, tracks)
    best: list[tuple[int, int]] = []
    best_cost = None
    for perm in permutations(range(large), small):
        pairs = [(i, j) if tracks_first else (j, i) for i, j in enumerate(perm)]
        cost = sum(allowed.get(pair, UNMATCHED) for pair in pairs)
        if best_cost is None or cost < best_cost:
            best, best_cost = [pair for pair in pairs if pair in allowed], cost
    return best
