import numpy as np
import pytest

from host import CANONICAL_GESTURES, DepthFrame, Gesture, GestureState, GestureType, Hand, HandState, Intrinsics


def test_depth_frame_owns_a_read_only_copy():
    source = np.full((4, 6), 1000, np.uint16)
    frame = DepthFrame(source, Intrinsics(5, 5, 3, 2))
    source[:] = 7
    assert frame.data[0, 0] == 1000
    with pytest.raises(ValueError):
        frame.data[0, 0] = 1


def test_depth_frame_rejects_wrong_dtype():
    with pytest.raises(ValueError, match="uint16"):
        DepthFrame(np.zeros((4, 4), np.float32), Intrinsics(1, 1, 0, 0))


@pytest.mark.parametrize("point", [(0.0, 0.0, 1500.0), (-412.5, 230.0, 2800.0), (900.0, -600.0, 4000.0)])
def test_world_and_depth_pixels_convert_both_ways(point):
    k = Intrinsics.from_fov(640, 480, 57, 43)
    u, v, z = k.world_to_depth(*point)
    assert np.allclose(k.depth_to_world(u, v, z), point)


def test_pixel_convention_matches_design():
    k = Intrinsics(500, 500, 320, 240)
    x, y, z = k.depth_to_world(420, 140, 2000)  # right of and above the centre
    assert x > 0 and y > 0 and z == 2000


def test_canonical_names_are_shared_across_middlewares():
    assert GestureType.WAVE.canonical == GestureType.WAVING.canonical == "wave"
    assert GestureType.CLICK.canonical == GestureType.PUSH.canonical == "click"
    assert {t.canonical for t in GestureType if t is not GestureType.LEARNED} == set(CANONICAL_GESTURES)
    assert GestureType.from_canonical("swipe_up") is GestureType.SWIPE_UP


def test_gesture_event_line_has_the_design_keys():
    g = Gesture(GestureType.PUSH, GestureState.COMPLETE, (1.0, 2.0, 3.0), hand_id=2, timestamp=1.5)
    line = g.to_json()
    assert line["name"] == "click" and line["native"] == "PUSH" and line["state"] == "complete"
    assert set(line) == {"t", "type", "name", "native", "state", "hand", "side", "position", "confidence"}


def test_a_hand_is_in_view_until_lost_or_absent():
    states = {s: Hand(1, s, (0.0, 0.0, 1000.0)).in_view for s in HandState}
    assert states == {HandState.NEW: True, HandState.TRACKING: True, HandState.TOUCHING_FOV: True,
                      HandState.LOST: False, HandState.ABSENT: False}
