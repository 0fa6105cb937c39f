"""Hand candidates on a hand-made body frame (mm): which ends of the user count as hands."""
from __future__ import annotations

import numpy as np

from backends.engine.hands import HandDetector, HandOptions
from backends.engine.segmentation import Grid, Segment
from backends.engine.trunk import Body

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
    frame = Body(torso=np.array([0.0, -90.0, 2610.0]), head=np.array([0.0, 330.0, face_z + 110.0]),
                 shoulder_y=150.0, hip_y=-400.0, surface_z=2500.0, face_z=face_z, core=body)
    return Segment(mask, grid), frame


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
