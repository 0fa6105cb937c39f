"""Coordinate spaces: normalised depth-image fractions and stage pixels through the calibration."""
import time

import numpy as np
import pytest

from host import (DepthFrame, Frame, Gesture, GestureState, GestureType, Hand, HandState, Intrinsics, Side,
                  Stage)
from tests.effects.osc.helpers import K, Script, hand_at, make_osc, run_show

SCRIPT = Script(n=10, gestures=())


def right_hands(receiver) -> dict[int, list[float]]:
    """{frame index: [x, y, z]} of the right hand in every bundle received."""
    assert receiver.wait_for(lambda r: r.has_frame(SCRIPT.n))
    out = {}
    for packet in receiver.packets:
        if packet.bundle:
            (_, _, (_, t, _)), *hands = packet.messages
            out.update({round(t * 30): args[3:6] for _, _, args in hands if args[1] == "right"})
    assert out
    return out


def test_normalized_is_the_place_in_the_depth_image_and_the_depth_range(receiver):
    run_show([make_osc(destinations=[receiver.address], space="normalized", depth_range=[1000, 3000])], script=SCRIPT)
    for i, (x, y, z) in right_hands(receiver).items():
        u, v, _ = K.world_to_depth(*hand_at(Side.RIGHT, i))
        assert (x, y, z) == pytest.approx((u / 640, v / 480, (hand_at(Side.RIGHT, i)[2] - 1000) / 2000), rel=1e-5)
        assert 0.5 < x < 1 and 0 < y < 1  # the right hand is on the image's right half


def test_stage_pixels_go_through_the_profiles_calibration(receiver):
    calibration = np.array([[2.0, 0.1, 30.0], [0.0, 1.5, -20.0], [0.0, 0.0, 1.0]])
    stage = Stage((1920, 1080), 240.0, "truth", calibration=calibration.tolist())
    run_show([make_osc(destinations=[receiver.address], space="stage")], script=SCRIPT, stage=stage)
    for i, (x, y, z) in right_hands(receiver).items():
        u, v, depth = K.world_to_depth(*hand_at(Side.RIGHT, i))
        assert (x, y, z) == pytest.approx((2 * u + 0.1 * v + 30, 1.5 * v - 20, depth), rel=1e-5)


def test_stage_pixels_without_calibration_stretch_the_depth_image(receiver):
    run_show([make_osc(destinations=[receiver.address], space="stage")], script=SCRIPT,
             stage=Stage((1280, 720), 240.0, "truth"))
    for i, (x, y, _) in right_hands(receiver).items():
        u, v, _ = K.world_to_depth(*hand_at(Side.RIGHT, i))
        assert (x, y) == pytest.approx((u * 2, v * 1.5), rel=1e-5)


def test_a_gesture_before_the_first_frame_waits_for_its_geometry_then_goes_first(receiver):
    effect = make_osc(destinations=[receiver.address], space="normalized")
    effect.setup(Stage((640, 480), 30.0, "truth"))
    depth = DepthFrame(np.zeros((480, 640), np.uint16), K)
    hand = Hand(1, HandState.TRACKING, (0.0, 0.0, 2000.0), Side.RIGHT)
    effect.on_gesture(Gesture(GestureType.WAVE, GestureState.COMPLETE, (0.0, 0.0, 2000.0), 1, Side.RIGHT))
    time.sleep(0.1)
    assert receiver.packets == []
    effect.on_frame(Frame(1, time.time(), depth, (hand,), (), "truth"))
    assert receiver.wait_for(lambda r: len(r.packets) == 2)
    effect.close()
    gesture, bundle = receiver.packets
    assert gesture.messages[0][0] == "/issv/gesture" and gesture.messages[0][2][4:6] == [0.5, 0.5]
    assert bundle.bundle


def test_frames_without_depth_are_projected_as_a_kinect_with_one_warning(receiver):
    warnings = []
    effect = make_osc(destinations=[receiver.address], space="normalized", warn=warnings.append)
    effect.setup(Stage((640, 480), 30.0, "network"))
    hand = Hand(1, HandState.TRACKING, (300.0, 0.0, 2000.0), Side.RIGHT)
    for seq in (1, 2, 3):
        effect.on_frame(Frame(seq, time.time(), None, (hand,), (), "network"))
    assert receiver.wait_for(lambda r: len(r.messages("/issv/hand")) == 3)
    effect.close()
    assert len(warnings) == 1 and "backend 'network' sends frames without one" in warnings[0]
    u, v, _ = Intrinsics.from_fov(640, 480, 57, 43).world_to_depth(300.0, 0.0, 2000.0)
    assert receiver.messages("/issv/hand")[0][2][3:5] == pytest.approx([u / 640, v / 480], rel=1e-6)
