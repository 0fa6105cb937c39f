"""What the segmenter takes for a person and for the floor, on rendered rooms and real takes."""
from __future__ import annotations

import numpy as np
import pytest

from backends.engine import segmentation
from backends.engine.segmentation import SegmentationOptions, Segmenter
from host import DepthFrame, Intrinsics
from tests.backends.engine.performer import frames, idle

SIZE = {"width": 320, "height": 240}


@pytest.mark.parametrize("distance_mm, wall_mm", [(1000, 1500), (1500, 2200), (2000, 2600)])
def test_a_child_before_a_near_wall_keeps_its_legs(distance_mm, wall_mm):
    """A child (1.15 m) with the back wall 0.5-0.7 m behind: the floor enters the picture only 2.8 m
    away, behind the wall, so no floor is in view. A plane through the camera fits any band of the
    picture's bottom rows (it is seen edge on), the wall's and the child's legs included; a level
    plane through the wall has the rest of the wall under it. Taken for the floor, either cut the
    child off at the knees or the hips (at 1.5 m, the child was lost in 32 of 102 frames)."""
    waving = frames([idle(0.5), {"action": "wave"}, idle(0.5)], height_mm=1150, distance_mm=distance_mm,
                    wall_mm=wall_mm, **SIZE)
    segmenter = Segmenter(SegmentationOptions())
    found = [segmenter.people(f) for f in waving]
    assert all(len(people) == 1 for people in found)
    assert all(people[0].segment.mask[-1].any() for people in found)  # down to the picture's bottom


def shelf(height_mm: float, width: int = 320, height: int = 240) -> DepthFrame:
    """A wall 4 m away; at the picture's left edge a surface 3.5 m away, 250 mm wide, its bottom
    300 mm below the camera and `height_mm` tall, over a dark cabinet the sensor gets no reading
    from, down to the picture's bottom 1.1 m lower (the real OpenNI take's shelf, 0.7 m tall)."""
    k = Intrinsics.from_fov(width, height, 57.0, 43.0)
    v, u = np.mgrid[0:height, 0:width].astype(np.float64)
    x, y = (u - k.cx) / k.fx * 3500, (k.cy - v) / k.fy * 3500  # mm at the surface's depth
    z = np.full((height, width), 4000.0)
    left = x <= x.min() + 250
    z[left & (y >= -300) & (y <= -300 + height_mm)] = 3500
    z[left & (y < -300)] = 0
    return DepthFrame(np.round(z).astype(np.uint16), k)


@pytest.mark.parametrize("height_mm, whole_mm, people", [(700, None, 0), (700, 1, 1), (1300, None, 1)])
def test_a_surface_floating_over_no_readings_is_a_person_only_if_as_tall_as_one(height_mm, whole_mm, people):
    """Nobody floats: a surface shorter than anyone standing, with 1.1 m without a reading under it
    (no legs, no floor, nothing in front), is furniture, though person-sized for the other rules.
    As tall as a person, it may be one (a clip with its background removed shows nothing under
    the feet)."""
    options = SegmentationOptions(floor=False)
    if whole_mm is not None:
        options = SegmentationOptions(floor=False, min_whole_user_height_mm=whole_mm)
    assert len(Segmenter(options).people(shelf(height_mm))) == people


def test_someone_whose_legs_are_in_a_near_childs_shadow_is_still_found(monkeypatch):
    """The `range` scene: an adult 4.2 m away walks behind a child 0.9 m from the camera, whose
    shadow (no readings, up to the sensor's baseline wide beside the child) hides the adult's legs.
    Nobody the segmenter finds without the rule is lost with it; without the shadow, some are."""
    scene = frames(scene="range", **SIZE)

    def found(options: SegmentationOptions) -> list[int]:
        segmenter = Segmenter(options)
        return [len(segmenter.people(f)) for f in scene]

    counts = found(SegmentationOptions(min_whole_user_height_mm=1))
    assert found(SegmentationOptions()) == counts
    monkeypatch.setattr(segmentation, "SHADOW_MM", 0)
    assert sum(found(SegmentationOptions())) < sum(counts)
