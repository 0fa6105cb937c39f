"""A performer's anatomy from their height above the floor, or above their feet: an adult's as it is,
a child's scaled down."""
from dataclasses import replace

import numpy as np
import pytest

from backends.engine.anatomy import Stature, scaled
from backends.engine.hands import HandOptions
from backends.engine.segmentation import Grid, Segment
from backends.engine.skeleton import SkeletonOptions
from backends.engine.smoothing import SmoothingOptions
from backends.engine.trunk import BodyEstimator, BodyOptions
from tests.backends.engine.test_trunk import CELL_MM, PLANE_MM, silhouette


def stature(*heights: float) -> Stature:
    s = Stature()
    for h in heights:
        s.add(h)
    return s


@pytest.mark.parametrize("height_mm, scale", [(1900, 1.0), (1500, 1.0), (1200, 0.8), (900, 0.6), (300, 0.5)])
def test_adults_keep_the_anatomy_and_a_child_is_scaled_by_their_height(height_mm, scale):
    assert stature(height_mm).scale == pytest.approx(scale)  # from the first crown on


def test_a_crouch_does_not_shrink_the_body():
    assert Stature().scale == 1.0
    assert stature(*([1200] * 20 + [700] * 60)).scale == pytest.approx(0.8)  # crouched for two seconds


def test_lengths_and_areas_scale_and_nothing_else():
    adult = HandOptions()
    child = scaled(adult, 0.5)
    assert child.palm_radius_mm == adult.palm_radius_mm / 2 and child.palm_area_m2 == adult.palm_area_m2 / 4
    assert child.max_hands == adult.max_hands and scaled(adult, 1.0) is adult
    assert scaled(SkeletonOptions(), 0.5).upper_arm_mm == tuple(v / 2 for v in SkeletonOptions().upper_arm_mm)


def test_a_child_standing_on_a_floor_gets_a_childs_trunk():
    """A crown 1.2 m above the floor: the shoulders and the spine are placed by a child's proportions,
    nearer the crown; without a floor in view, or feet (the trunk ends in the middle of the picture,
    as wide as a trunk), the adult's stay."""
    floor = np.array([0.0, 1.0, 0.0, 1000.0])  # the floor 1 m below the camera's axis
    child = silhouette(100.0, (200.0, PLANE_MM))  # the crown 200 mm above the axis: 1.2 m tall
    on_floor, no_floor = (BodyEstimator(BodyOptions(), SmoothingOptions(enabled=False)) for _ in range(2))
    for i in range(3):
        seen = on_floor.estimate(replace(child, floor=floor), i / 30)
        unknown = no_floor.estimate(child, i / 30)
    assert seen.scale == pytest.approx(0.8) and unknown.scale == 1.0
    assert seen.head[1] - seen.torso[1] == pytest.approx(0.8 * (unknown.head[1] - unknown.torso[1]), abs=25)


def standing(height_mm: float, legs_end_mm: float | None = None, under_feet: bool = False) -> Segment:
    """A person `height_mm` tall seen from the front with the background removed, the feet 1 m below
    the camera's axis: a head, a trunk 400 mm wide over half the height and two legs 60 mm apart,
    170 mm wide at the hips (an adult's thighs) and 100 at the feet, down to the feet or to
    `legs_end_mm` (legs the camera reads nothing from below there);
    `under_feet`: something read under the feet."""
    rows, cols = 128, 60  # the picture reaches 1.9 m below the axis
    v, u = np.mgrid[0:rows, 0:cols].astype(np.float32)
    x, y = (u - cols / 2) * CELL_MM, (rows / 4 - v) * CELL_MM
    feet, crown = -1000.0, height_mm - 1000.0
    hips, neck = feet + 0.5 * height_mm, crown - 0.17 * height_mm
    leg_width = 100 + 70 * (y - feet) / (hips - feet)
    legs_end = feet if legs_end_mm is None else legs_end_mm
    legs = (np.abs(x) >= 30) & (np.abs(x) <= 30 + leg_width) & (y >= legs_end) & (y < hips)
    body = legs | ((np.abs(x) <= 200) & (y >= hips) & (y <= neck)) | ((np.abs(x) <= 70) & (y > neck) & (y <= crown))
    z = np.where(body, PLANE_MM, 0).astype(np.float32)
    mask = body.copy()
    if under_feet:
        z[(y < feet) & (np.abs(x) <= 300)] = PLANE_MM - 200
    grid = Grid(z, np.where(z > 0, x, 0), np.where(z > 0, y, 0), np.full_like(z, CELL_MM ** 2),
                CELL_MM / PLANE_MM, CELL_MM / PLANE_MM)
    return Segment(mask, grid)


@pytest.mark.parametrize("person, scale", [
    (standing(1200), 0.8),  # a child, the feet in view
    (standing(1800), 1.0),  # an adult
    (standing(1800, legs_end_mm=-200), 1.0),  # an adult whose legs read nothing below the thighs: no child
    (standing(1200, under_feet=True), 1.0),  # something under the feet: a floor not found, or what hides them
    (standing(850), 1.0),  # shorter than anyone standing: a body cut off (seated at a desk too near to read)
    (standing(1700).crop((slice(0, 75), slice(0, 60))), 1.0),  # legs cut off by the picture's bottom
])
def test_without_a_floor_the_height_is_the_crowns_above_the_feet_when_they_are_in_view(person, scale):
    estimator = BodyEstimator(BodyOptions(), SmoothingOptions(enabled=False))
    for i in range(3):
        body = estimator.estimate(person, i / 30)
    assert body.scale == pytest.approx(scale)
