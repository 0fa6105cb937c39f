"""What the segmenter takes for a person and for the floor, on rendered rooms and real takes."""
from __future__ import annotations

import numpy as np
import pytest

from backends.engine import segmentation
from backends.engine.segmentation import SegmentationOptions, Segmenter
from backends.engine.tracker import HandTracker
from host import DepthFrame, Intrinsics
from sources.clip import Clip
from tests.backends.engine.performer import frames, idle
from tests.conftest import real_data

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


def standing(arm: str | None = None, wall_mm: float | None = None, second: tuple[float, float] | None = None,
             bridged: bool = False, width: int = 320, height: int = 240) -> DepthFrame:
    """Someone 2.5 m away, head, trunk (400 mm wide) and legs on one plane, before a wall at `wall_mm`
    (None: the background removed). `arm`: "across", a forearm 350 mm in front of the chest from the
    shoulder down across it and out past the hip on the other side (UTD-MHAD s3 and s4 swipe so),
    whose depth edges cut the body in two; "side", an arm held against the side; "loop", that arm's
    hand on the hip, the elbow out, the wall seen through the loop it makes. `second`: another person
    (mm to the right, mm further away); `bridged`: an arm from the first one's side to the second's,
    sloping in depth without a depth edge, which makes the two one surface."""
    k = Intrinsics.from_fov(width, height, 57.0, 43.0)
    v, u = np.mgrid[0:height, 0:width].astype(np.float64)

    def at(depth: float) -> tuple[np.ndarray, np.ndarray]:
        return (u - k.cx) / k.fx * depth, (k.cy - v) / k.fy * depth

    def body(right_mm: float, depth: float) -> np.ndarray:
        x, y = at(depth)
        x = x - right_mm
        return (((np.abs(x) <= 200) & (y >= -200) & (y <= 400)) | ((np.abs(x) <= 80) & (y > 400) & (y <= 650))
                | ((np.abs(np.abs(x) - 100) <= 70) & (y >= -1000) & (y < -200)))

    z = np.full((height, width), wall_mm or 0.0)
    if second is not None:
        right_mm, behind_mm = second
        z[body(right_mm, 2500 + behind_mm)] = 2500 + behind_mm
        if bridged:  # from (200, 2500) to (right_mm - 200, 2500 + behind_mm), where each column's ray meets it
            ray, _ = at(1.0)
            along = (2500 * ray - 200) / (right_mm - 400 - behind_mm * ray)
            depth = 2500 + behind_mm * along
            _, up = at(depth)
            reaching = (along >= 0) & (along <= 1) & (up >= 0) & (up <= 100)
            z[reaching] = depth[reaching]
    z[body(0, 2500)] = 2500
    x, y = at(2500.0)
    beside = (x > 200) & (x <= 500) & (y >= -150) & (y <= 300)
    if arm == "side":
        z[beside] = 2500
    elif arm == "loop":
        z[beside & ~((x > 260) & (x <= 440) & (y >= -90) & (y <= 240))] = 2450
    elif arm == "across":
        x, y = at(2150.0)
        z[(np.abs(y - (150 - 1.2 * x)) <= 60) & (np.abs(x) <= 320)] = 2150
    return DepthFrame(np.round(z).astype(np.uint16), k)


def test_an_arm_across_the_body_does_not_cut_the_user_in_two():
    """A forearm across the chest cuts the body into two surfaces along its depth edges. Seen first
    so, they look like two people. Seen whole a frame before, the user stays one person, head to feet
    (a trunk left out shifts the body's depth as a lunge does; a head left out is no head)."""
    assert len(Segmenter(SegmentationOptions(floor=False)).people(standing("across"))) == 2
    segmenter = Segmenter(SegmentationOptions(floor=False))
    segmenter.people(standing())
    assert len(segmenter.people(standing("across"))) == 1
    user = segmenter.segment(standing("across"))
    heights = user.grid.y[user.mask]
    assert heights.max() > 600 and heights.min() < -900, (heights.max(), heights.min())


def test_the_wall_seen_where_the_arm_was_does_not_join_the_user():
    """Hands on the hips: the wall 0.6 m behind shows through the loop of the arm, where the arm was
    a frame before. That surface is no piece of the user cut off (its depth changed by more than a
    depth edge): only the cells at the loop's rim are theirs, as around any nearer surface."""
    segmenter = Segmenter(SegmentationOptions(floor=False))
    segmenter.segment(standing("side", wall_mm=3100))
    user = segmenter.segment(standing("loop", wall_mm=3100))
    g = user.grid
    across, up = g.x / np.maximum(g.z, 1), g.y / np.maximum(g.z, 1)  # the loop's middle: (350, 75) mm at the arm
    middle = (np.abs(across - 350 / 2450) < 0.01) & (np.abs(up - 75 / 2450) < 0.01) & (g.z > 3000)
    assert middle.any() and not (user.mask & middle).any()


@pytest.mark.parametrize("before, now", [
    ({"second": (400, 0)}, {"second": (500, 0)}),  # side by side, touching; then a step apart
    ({"second": (600, 377), "bridged": True}, {"second": (600, 377), "arm": "side"}),  # an arm reaching back
])
def test_two_people_who_were_one_surface_for_a_frame_are_two_again(before, now):
    """Two people touching, or joined for a frame by an arm reaching from one to the other without a
    depth edge, are one surface. Apart again, they are two people: with the background between them,
    or with the second a body's thickness behind the first (whose arm, held out, now hides part of
    them: cut off by something nearer, as an arm across the body cuts its own body)."""
    segmenter = Segmenter(SegmentationOptions(floor=False))
    assert len(segmenter.people(standing(wall_mm=4000, **before))) == 1
    assert len(segmenter.people(standing(wall_mm=4000, **now))) == 2


@pytest.mark.parametrize("take", ["a1_s3_t2_swipe_left", "a1_s4_t2_swipe_left"])
def test_a_real_swipe_across_the_chest_leaves_the_bodys_depth_where_it_was(take):
    """UTD-MHAD s3's and s4's swipes to the left cross the chest, cutting the body in two for a frame.
    The torso's depth stays within the 40 mm that real swipes move it: left out of the user, the trunk
    had the body's depth jump 75-81 mm forward there (120 mm for a performer 1.15 times as big, a lunge
    to the steadiness rule, and the swipe was lost)."""
    clip = Clip(real_data("utd-mhad-dev", "clips", f"{take}.npz"))
    tracker = HandTracker()
    depths = [tracker.process(clip.frame(i, i)).body["torso"][2] for i in range(len(clip))]
    assert np.ptp(depths) <= 40, np.ptp(depths)


def test_cells_without_readings_cut_no_surface():
    """A patch without readings (a dark or shiny object) is nothing near: the cells around it stay
    one surface with the rest; a column of dropped readings joins the two sides; neither is part of it."""
    z = np.full((40, 60), 2000, np.float32)
    z[10:15, 10:15] = 0  # a patch without readings
    z[:, 30] = 0  # a column of dropped readings
    flat = np.zeros_like(z)
    grid = segmentation.Grid(z, flat, flat, flat, 0.01, 0.01)
    count, labels = Segmenter(SegmentationOptions(floor=False))._surfaces(grid, z > 0)
    assert count == 2  # the background label and one surface
    assert (labels[z > 0] == 1).all() and (labels[z == 0] == 0).all()
