"""The engine's median and percentiles give numpy's results exactly, whatever the size, order and dtype."""
from __future__ import annotations

import numpy as np
import pytest

from backends.engine.quantiles import median, percentile, percentiles

QS = (0, 1, 5, 10, 25, 33.3, 50, 66.7, 75, 90, 95, 99, 100)


def samples():
    """Arrays as the engine meets them: depths in whole mm (float32), world mm, ties, one or two values."""
    rng = np.random.default_rng(7)
    for n in (1, 2, 3, 4, 5, 8, 9, 64, 65, 257):
        yield rng.integers(800, 4000, n).astype(np.float32)  # grid depths: whole mm, many ties
        yield rng.normal(0, 300, n)  # world mm, float64
        yield rng.normal(0, 300, n).astype(np.float32)
        yield np.full(n, 1234.5, np.float32)


@pytest.mark.parametrize("a", list(samples()), ids=lambda a: f"{a.dtype}x{a.size}")
def test_median_and_percentiles_are_numpys(a: np.ndarray) -> None:
    assert median(a) == np.median(a)
    assert median(a).dtype == np.median(a).dtype
    for q in QS:
        expected = np.percentile(a, q)
        assert percentile(a, q) == expected, q
        assert percentile(a, q).dtype == expected.dtype, q
    assert percentiles(a, QS) == [np.percentile(a, q) for q in QS]


def test_the_input_is_left_as_it_was() -> None:
    a = np.array([5.0, 1.0, 4.0, 2.0, 3.0])
    before = a.copy()
    median(a), percentile(a, 90), percentiles(a, (10, 50))
    assert np.array_equal(a, before)
