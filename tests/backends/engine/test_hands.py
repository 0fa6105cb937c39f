"""Hand candidates on a hand-made body frame (mm): which ends of the user count as hands."""
from __future__ import annotations

import numpy as np

from backends.engine.hands import HandDetector, HandOptions
from backends.engine.segmentation import Grid, Segment
from backends.engine.trunk import Body, UserBox

CELL_MM = 20.0


def scene(patches: list[tuple[slice, slice, float]], face_z: float = 2500.0) -> tuple[Segment, Body]:
    """A flat trunk and head 2.5 m away on a 20 mm grid, with patches (rows, columns, depth) in front;
    `face_z`, where the body frame puts the face."""
    rows, cols = 60, 60
    v, u = np.mgrid[0:rows, 0:cols].astype(np.float32)
    x, y = (u - cols / 2) * CELL_MM, (rows / 3 - v) * CELL_MM  # y = 0 at row 20, up is +
    z = np.zeros((rows, cols), np.float32)
    body = (np.abs(x) <= 200) & (y <= 150) & (y >= -700) | (np.abs(x) <= 90) & (y > 150) & (y <= 450)
    z[body] = 2500.0
    for r, c, depth in patches:
        z[r, c] = depth
    mask = z > 0
    grid = Grid(z, np.where(mask, x, 0), np.where(mask, y, 0), np.full_like(z, CELL_MM ** 2),
                CELL_MM / 2500, CELL_MM / 2500)
    seg = Segment(mask, grid)
    user = UserBox.of(seg)
    frame = Body(torso=np.array([0.0, -90.0, 2610.0]), head=np.array([0.0, 330.0, face_z + 110.0]),
                 shoulder_y=150.0, hip_y=-400.0, surface_z=2500.0, face_z=face_z, user=user, core=body[user.box])
    return seg, frame


def test_an_end_by_the_neck_is_no_hand_and_one_a_forearm_away_is():
    """Something in front of the throat (a chin, a shoulder seen at an angle) sticks out of the body
    like a hand; only ends at least a forearm from the base of the neck (the spine's depth, at the
    shoulder line) are hands."""
    by_the_neck = (slice(12, 15), slice(29, 33), 2370.0)  # at the throat, 130 mm in front: 245 mm from the neck
    held_out = (slice(12, 16), slice(42, 46), 2100.0)  # x 240-300 mm, y 80-160 mm, 400 mm in front
    detect = HandDetector(HandOptions()).detect
    assert detect(*scene([by_the_neck])) == []
    found = detect(*scene([held_out]))
    assert len(found) == 1 and 250 < found[0].position[0] < 300
    assert len(HandDetector(HandOptions(min_reach_mm=0)).detect(*scene([by_the_neck]))) == 1


def test_a_head_leaning_forward_is_no_hand_and_a_hand_before_the_face_is():
    """Bowing or sitting down brings the head well in front of the chest, where a pushing hand
    would be; in front of the face, only what is in front of the face itself is a hand."""
    head = (slice(2, 12), slice(26, 35), 2330.0)  # the whole head, 170 mm in front of the chest
    hand = (slice(4, 9), slice(28, 33), 2150.0)  # before that face, 180 mm in front of it
    detect = HandDetector(HandOptions()).detect
    assert detect(*scene([head], face_z=2330.0)) == []
    found = detect(*scene([head, hand], face_z=2330.0))
    assert len(found) == 1 and abs(found[0].position[2] - 2150.0 - HandOptions().hand_depth_mm) < 30
    assert len(detect(*scene([head]))) == 1  # a face where the chest is: the head sticks out like a hand


def test_a_hand_at_the_chest_is_found_from_nearer_than_an_arm_reaching_out():
    """A push starts with the hand at the chest, 90-120 mm in front of it: a hand there, with nothing
    of the arm farther out and standing out of the chest beside it, is a hand (found at its most
    forward end); without the nearer threshold (near_front_mm = front_mm) it is not, nor is the trunk
    bulging as far forward in one smooth surface."""
    at_chest = (slice(18, 23), slice(36, 40), 2400.0)  # x 120-180 mm, y 40 to -40 mm, 100 mm in front
    found = HandDetector(HandOptions()).detect(*scene([at_chest]))
    assert len(found) == 1
    assert np.allclose(found[0].position, (150.0, 0.0, 2400.0 + HandOptions().hand_depth_mm), atol=30)
    assert HandDetector(HandOptions(near_front_mm=120)).detect(*scene([at_chest])) == []
    lower = (slice(33, 38), slice(36, 40), 2400.0)  # the same 300 mm lower, in front of the belly: no push starts there
    assert HandDetector(HandOptions()).detect(*scene([lower])) == []
    # the trunk itself bulging as far forward, smoothly (leaning, or moving ahead of its estimated surface)
    bulge = [(slice(17, 24), slice(35, 41), 2450.0), (slice(18, 23), slice(36, 40), 2400.0)]
    assert HandDetector(HandOptions()).detect(*scene(bulge)) == []
    assert len(HandDetector(HandOptions(arm_edge_mm=50)).detect(*scene(bulge))) == 1


def test_an_arm_reaching_out_is_judged_without_its_cells_near_the_chest():
    """A forearm raised 200 mm out, its upper arm 100 mm in front of the chest, its hand over by the face
    (60 mm in front of the chest): where the arm joins the body is its elbow, so its end is up by the
    head. Taken whole from 90 mm, the patch joins the body at the shoulder and by the face too, and
    its end flips to the elbow: the cells near the chest do not count for an arm reaching farther."""
    head = (slice(0, 12), slice(26, 35), 2440.0)
    upper_arm = (slice(12, 22), slice(36, 41), 2400.0)  # x 120-200 mm, y 160 to -20 mm
    forearm = (slice(2, 12), slice(35, 38), 2300.0)  # x 100-140 mm, y 180-360 mm
    hand = (slice(0, 4), slice(31, 36), 2370.0)  # x 20-100 mm, y 340-400 mm, 70 mm in front of the face
    arm = scene([head, upper_arm, forearm, hand], face_z=2440.0)
    found = HandDetector(HandOptions()).detect(*arm)
    without = HandDetector(HandOptions(near_front_mm=120)).detect(*arm)
    assert len(found) == 1 and np.array_equal(found[0].position, without[0].position)
    assert found[0].position[1] > 150  # above the shoulder line
    flipped = HandDetector(HandOptions(front_mm=90)).detect(*arm)
    assert len(flipped) == 1 and flipped[0].position[1] < 150
