"""The body frame on hand-made silhouettes (mm): where the shoulder line and the head are."""
from __future__ import annotations

import numpy as np

from backends.engine.segmentation import Grid, Segment
from backends.engine.smoothing import SmoothingOptions
from backends.engine.trunk import BodyEstimator, BodyOptions

CELL_MM = 20.0
PLANE_MM = 2500.0


def silhouette(trunk_top_mm: float, head: tuple[float, float] | None, head_x: float = 0.0,
               head_width: float = 140.0) -> Segment:
    """A trunk 400 mm wide from 700 mm below the origin up to `trunk_top_mm`, on the body's plane, and
    a head `head_width` wide centred at `head_x` from the trunk's top up to `head` = (top mm, depth mm)."""
    rows, cols = 80, 60
    v, u = np.mgrid[0:rows, 0:cols].astype(np.float32)
    x, y = (u - cols / 2) * CELL_MM, (rows / 2 - v) * CELL_MM
    z = np.zeros((rows, cols), np.float32)
    z[(np.abs(x) <= 200) & (y >= -700) & (y <= trunk_top_mm)] = PLANE_MM
    if head is not None:
        z[(np.abs(x - head_x) <= head_width / 2) & (y > trunk_top_mm) & (y <= head[0])] = head[1]
    mask = z > 0
    grid = Grid(z, np.where(mask, x, 0), np.where(mask, y, 0), np.full_like(z, CELL_MM ** 2),
                CELL_MM / PLANE_MM, CELL_MM / PLANE_MM)
    return Segment(mask, grid)


def test_a_head_rising_in_front_of_the_body_is_no_arm_hiding_the_crown():
    """Standing up from a bend brings the head up in front of the body, outside the body's plane,
    as an arm swiping past the face is. Only the arm leaves the user's top where it was: the crown
    seen bent over must not be held as the body rises (the shoulder line, the hips and every hand
    judged from them would stay down there)."""
    estimator = BodyEstimator(BodyOptions(), SmoothingOptions(enabled=False))
    bent = estimator.estimate(silhouette(-100.0, (0.0, PLANE_MM)), 0.0)  # the crown 700 mm above the hips
    risen = estimator.estimate(silhouette(150.0, (500.0, PLANE_MM - 350)), 0.1)  # the head 350 mm in front
    assert risen.shoulder_y - bent.shoulder_y > 200
    assert risen.head[1] > 300


def test_a_head_leaning_out_of_the_column_above_the_spine_is_found_whole():
    """Bent forward walking in, the head is beside the spine: the column the head is looked for in
    holds less than half of it, and the head joint at the middle of that part would leave the far
    side of the head a forearm away from it, where a raised hand is looked for."""
    estimator = BodyEstimator(BodyOptions(), SmoothingOptions(enabled=False))
    body = estimator.estimate(silhouette(0.0, (300.0, PLANE_MM), head_x=-170.0, head_width=200.0), 0.0)
    assert abs(body.head[0] + 170.0) < 40
