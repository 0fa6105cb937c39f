"""A performer's anatomy from their height above the floor: an adult's as it is, a child's scaled down."""
from dataclasses import replace

import numpy as np
import pytest

from backends.engine.anatomy import MIN_FRAMES, Stature, scaled
from backends.engine.hands import HandOptions
from backends.engine.skeleton import SkeletonOptions
from backends.engine.smoothing import SmoothingOptions
from backends.engine.trunk import BodyEstimator, BodyOptions
from tests.backends.engine.test_trunk import PLANE_MM, silhouette


def stature(*heights: float) -> Stature:
    s = Stature()
    for h in heights:
        s.add(h)
    return s


@pytest.mark.parametrize("height_mm, scale", [(1900, 1.0), (1500, 1.0), (1200, 0.8), (900, 0.6), (300, 0.5)])
def test_adults_keep_the_anatomy_and_a_child_is_scaled_by_their_height(height_mm, scale):
    assert stature(*[height_mm] * MIN_FRAMES).scale == pytest.approx(scale)


def test_the_height_is_trusted_after_a_few_crowns_and_a_crouch_does_not_shrink_the_body():
    assert stature(*[1200] * (MIN_FRAMES - 1)).scale == 1.0
    assert stature(*([1200] * 20 + [700] * 60)).scale == pytest.approx(0.8)  # crouched for two seconds


def test_lengths_and_areas_scale_and_nothing_else():
    adult = HandOptions()
    child = scaled(adult, 0.5)
    assert child.palm_radius_mm == adult.palm_radius_mm / 2 and child.palm_area_m2 == adult.palm_area_m2 / 4
    assert child.max_hands == adult.max_hands and scaled(adult, 1.0) is adult
    assert scaled(SkeletonOptions(), 0.5).upper_arm_mm == tuple(v / 2 for v in SkeletonOptions().upper_arm_mm)


def test_a_child_standing_on_a_floor_gets_a_childs_trunk():
    """A crown 1.2 m above the floor: the shoulders and the spine are placed by a child's proportions,
    nearer the crown; without a floor in view the adult's stay."""
    floor = np.array([0.0, 1.0, 0.0, 1000.0])  # the floor 1 m below the camera's axis
    child = silhouette(100.0, (200.0, PLANE_MM))  # the crown 200 mm above the axis: 1.2 m tall
    on_floor, no_floor = (BodyEstimator(BodyOptions(), SmoothingOptions(enabled=False)) for _ in range(2))
    for i in range(MIN_FRAMES + 1):
        seen = on_floor.estimate(replace(child, floor=floor), i / 30)
        unknown = no_floor.estimate(child, i / 30)
    assert seen.scale == pytest.approx(0.8) and unknown.scale == 1.0
    assert seen.head[1] - seen.torso[1] == pytest.approx(0.8 * (unknown.head[1] - unknown.torso[1]), abs=25)
