"""The synthetic performer: a Kinect-like depth image, really drawn where its ground truth says."""
from __future__ import annotations

import math

import numpy as np
import pytest

from host import CANONICAL_GESTURES, DepthFrame, Intrinsics, Side
from host.errors import ProfileError, UserError
from host.plugins import Registry
from host.profile import parse
from backends.truth import TruthBackend
from sources.synthetic import SyntheticOptions, SyntheticSource

SMALL = {"width": 160, "height": 120}  # enough pixels for truth checks, cheap to render


def source(**options) -> SyntheticSource:
    src = SyntheticSource(SyntheticOptions(**options))
    src.open()
    return src


def frames(src: SyntheticSource, limit: int = 100_000) -> list[DepthFrame]:
    out = []
    while len(out) < limit and (frame := src.read()) is not None:
        out.append(frame)
    return out


def one(action: str, **step) -> list[dict]:
    return [{"action": "idle", "duration": 0.5}, {"action": action, **step}, {"action": "idle", "duration": 0.5}]


def test_frames_are_kinect_v1_depth_images_at_exact_timestamps():
    src = source(seed=1)
    shown = frames(src, 5)
    assert src.fps == 30.0
    assert src.intrinsics == Intrinsics.from_fov(640, 480, 57, 43)
    for i, frame in enumerate(shown):
        assert frame.data.shape == (480, 640) and frame.data.dtype == np.uint16
        assert frame.intrinsics == src.intrinsics and frame.mirrored
        assert frame.frame_id == i and frame.timestamp == i / 30
    depth = shown[0].data
    assert 0 < np.count_nonzero(depth == 0) < depth.size * 0.05  # some holes, mostly readings
    body = depth[100:300, 300:340]  # the torso at ~2.5 m in front of a wall at ~4 m
    assert 2300 < np.median(body[body > 0]) < 2600


def test_the_320x240_mode_has_the_same_camera_at_half_the_resolution():
    src = source(width=320, height=240, seed=1)
    frame = src.read()
    assert frame.data.shape == (240, 320)
    assert src.intrinsics == Intrinsics.from_fov(640, 480, 57, 43).scaled(0.5, 0.5)


@pytest.mark.parametrize("size", [(640, 480), (320, 240)])
def test_hands_are_drawn_where_the_truth_puts_them(size):
    """Clean depth at each truth hand's pixel is that hand's surface, at most a hand's length (fingers
    pointing at the camera) in front of the palm centre."""
    src = source(width=size[0], height=size[1], noise=0, holes=0, background="none",
                 choreography=[{"action": a} for a in ("click", "swipe_up", "wave")])
    checked = 0
    for frame in frames(src)[::7]:
        for side, (x, y, z) in frame.truth.hands.items():
            u, v, _ = frame.world_to_depth((x, y, z))
            drawn = int(frame.data[int(round(v)), int(round(u))])
            assert 0 < z - drawn < 150, (frame.timestamp, side, drawn, z)
            checked += 1
    assert checked > 40


def test_a_pushed_hand_stands_out_in_front_of_the_body():
    """Mid-click the hand's pixel is far nearer than the torso: the hand itself is drawn, not the body behind."""
    src = source(noise=0, holes=0, choreography=one("click"))
    for frame in frames(src):
        if frame.truth.gestures and abs(frame.timestamp - (frame.truth.gestures[0].start + 0.35)) < 0.02:
            u, v, _ = frame.world_to_depth(frame.truth.hands[Side.RIGHT])
            torso_z = frame.truth.body["torso"][2]
            assert frame.data[round(v), round(u)] < torso_z - 250
            return
    pytest.fail("no frame in the middle of the push")


def wall_noise(distance_mm: float, noise: float = 1.0) -> float:
    """Standard deviation over time of flat back-wall pixels (depth = distance + 1.5 m)."""
    src = source(distance_mm=distance_mm, noise=noise, holes=0, seed=3, width=320, height=240,
                 choreography=[{"action": "idle", "duration": 0.4}])
    stack = np.stack([f.data[5:25, 5:60] for f in frames(src)]).astype(float)
    return float(np.mean(np.std(stack, axis=0)))


def test_depth_noise_grows_with_the_square_of_distance():
    near, far = wall_noise(1500), wall_noise(3500)  # wall at 3.0 m and 5.0 m
    assert 1.0 < near < far
    assert 2.0 < far / near < 4.0  # (5 / 3)^2 = 2.8
    assert wall_noise(1500, noise=0) == 0.0


def test_the_projector_shadow_falls_on_the_side_away_from_the_projector():
    """Raw Kinect images show the shadow left of a body; mirrored ones on its right."""
    for mirrored, shadow_on_right in ((True, True), (False, False)):
        depth = source(noise=0, holes=1, seed=2, mirrored=mirrored, choreography=[{"action": "idle"}]).read().data
        rows = depth[200:260]
        body = np.nonzero((rows[30] > 0) & (rows[30] < 3000))[0]
        left, right = rows[:, body.min() - 12: body.min()], rows[:, body.max() + 1: body.max() + 13]
        near_side, far_side = (right, left) if shadow_on_right else (left, right)
        assert np.mean(near_side == 0) > 0.3 > np.mean(far_side == 0)


def test_a_seed_reproduces_the_same_frames():
    a, b, c = (frames(source(seed=s, width=320, height=240), 5) for s in (7, 7, 8))
    assert all(np.array_equal(x.data, y.data) for x, y in zip(a, b))
    assert not all(np.array_equal(x.data, z.data) for x, z in zip(a, c))


@pytest.mark.parametrize("action", CANONICAL_GESTURES)
@pytest.mark.parametrize("hand", ["left", "right"])
def test_every_gesture_has_one_truth_interval_on_its_hand(action, hand):
    shown = frames(source(**SMALL, noise=0, choreography=one(action, hand=hand)))
    intervals = {g for f in shown for g in f.truth.gestures}
    assert len(intervals) == 1
    (g,) = intervals
    assert (g.name, g.side) == (action, Side(hand))
    inside = [f.timestamp for f in shown if f.truth.gestures]
    assert inside[0] >= g.start and inside[-1] <= g.end and len(inside) >= 3


def displacement(action: str, hand: str, **options) -> np.ndarray:
    """Truth palm movement (mm) from the first to the last frame of the gesture interval."""
    shown = [f for f in frames(source(**SMALL, noise=0, choreography=one(action, hand=hand), **options))
             if f.truth.gestures]
    side = Side(hand)
    return np.subtract(shown[-1].truth.hands[side], shown[0].truth.hands[side])


@pytest.mark.parametrize("hand", ["left", "right"])
@pytest.mark.parametrize("mirrored", [True, False])
def test_swipes_move_the_hand_the_way_the_performer_means(hand, mirrored):
    """swipe_right goes to the performer's right: +x on a mirrored image, -x on a raw one; 40-60 cm."""
    right = 1 if mirrored else -1
    for action, expected in (("swipe_right", right), ("swipe_left", -right)):
        dx = displacement(action, hand, mirrored=mirrored)[0]
        assert 400 < expected * dx < 600, (action, dx)


def test_vertical_swipes_click_and_hand_raise_move_as_named():
    assert 400 < displacement("swipe_up", "right")[1] < 600
    assert -600 < displacement("swipe_down", "right")[1] < -400
    src = source(**SMALL, noise=0, choreography=one("hand_raise"))
    raised = [f for f in frames(src) if f.truth.gestures][-1]
    assert raised.truth.hands[Side.RIGHT][1] > raised.truth.body["head"][1] + 100  # above the head


def test_click_pushes_the_hand_toward_the_camera_and_back():
    src = source(**SMALL, noise=0, choreography=one("click"))
    zs = [f.truth.hands[Side.RIGHT][2] for f in frames(src) if f.truth.gestures]
    assert 250 <= zs[0] - min(zs) <= 350
    assert abs(zs[-1] - zs[0]) < 30


def test_a_wave_oscillates_three_to_four_times_a_second_or_so():
    src = source(**SMALL, noise=0, choreography=one("wave"))
    xs = np.array([f.truth.hands[Side.RIGHT][0] for f in frames(src) if f.truth.gestures])
    crossings = np.count_nonzero(np.diff(np.sign(xs - np.median(xs))) != 0)
    assert 6 <= crossings <= 9  # 4 oscillations cross the centre about 8 times
    assert 150 <= xs.max() - xs.min() <= 250


def test_walking_crosses_the_stage_without_any_gesture():
    src = source(**SMALL, noise=0, choreography=[{"action": "walk", "x_mm": 900}, {"action": "walk", "x_mm": -300}])
    shown = frames(src)
    assert not any(f.truth.gestures for f in shown)
    torso_x = [f.truth.body["torso"][0] for f in shown]
    assert max(torso_x) > 850 and abs(torso_x[-1] + 300) < 30
    swing = [f.truth.hands[Side.RIGHT] for f in shown]
    assert max(p[1] for p in swing) < shown[0].truth.body["torso"][1]  # hands stay low: no swipe pose


def test_speed_scales_time_and_the_default_show_covers_every_action():
    normal, fast = SyntheticSource(SyntheticOptions()), SyntheticSource(SyntheticOptions(speed=2.0))
    assert 18 <= normal.timeline.length <= 26
    assert math.isclose(fast.timeline.length, normal.timeline.length / 2)
    assert sorted(g.name for g in normal.timeline.gestures) == sorted(CANONICAL_GESTURES)
    assert {s.action for s in normal.steps} == {"idle", "walk", *CANONICAL_GESTURES}


def test_intervals_never_touch_so_the_truth_backend_sees_each_once():
    """Through the truth backend: every interval gives one IN_PROGRESS and one COMPLETE, also when looping."""
    src = SyntheticSource(SyntheticOptions(**SMALL, noise=0, holes=0, loop=True, speed=4.0))
    backend = TruthBackend(src)
    backend.init()
    backend.start_hand_tracking()
    backend.start_gesture_detection()
    length = src.timeline.length
    events = []
    while (frame := backend.update()) is not None and frame.timestamp < 2 * length:
        events += [(g.name, g.state.value) for g in frame.gestures]
    assert frame.timestamp >= 2 * length  # looped on instead of ending
    names = sorted(CANONICAL_GESTURES) * 2
    assert sorted(n for n, s in events if s == "complete") == sorted(names)
    assert sorted(n for n, s in events if s == "in_progress") == sorted(names)


def test_the_show_ends_after_its_last_step_unless_looping():
    src = source(**SMALL, choreography=[{"action": "idle", "duration": 1.0}])
    assert len(frames(src)) == 30 and src.read() is None


def test_bad_choreography_files_are_named_with_the_step_and_what_is_expected(tmp_path):
    path = tmp_path / "show.toml"
    path.write_text('[[steps]]\naction = "idle"\n[[steps]]\naction = "jump"\n[[steps]]\naction = "wave"\nduration = -1\n')
    with pytest.raises(UserError) as caught:
        SyntheticSource(SyntheticOptions(choreography_file=str(path)))
    lines = str(caught.value).splitlines()
    assert lines[0].startswith(f"{path}: steps[1].action: expected 'idle', 'wave'")
    assert lines[0].endswith("got 'jump'")
    assert lines[1] == f"{path}: steps[2].duration: expected greater than 0, got -1"
    with pytest.raises(UserError, match="no such choreography file"):
        SyntheticSource(SyntheticOptions(choreography_file=str(tmp_path / "missing.toml")))
    path.write_text('[[steps]]\naction = "walk"\nx_mm = 3000\nduration = 1.0\n')
    with pytest.raises(UserError, match=r"steps\[0\]: walking 3000 mm .* is running; give a duration of at least 2.2 s"):
        SyntheticSource(SyntheticOptions(choreography_file=str(path)))


def test_a_profile_with_a_bad_inline_step_fails_validation_with_its_key_path(tmp_path):
    registry = Registry()
    registry.register("backends", TruthBackend, "test")
    registry.register("sources", SyntheticSource, "test")
    text = ('backend = "truth"\n[source]\nname = "synthetic"\n'
            'choreography = [{action = "wave", duration = 0.5}, {action = "walk"}]\n')
    with pytest.raises(ProfileError) as caught:
        parse(text, "profiles/x.toml", tmp_path, registry)
    assert caught.value.lines == [
        "profiles/x.toml: source.choreography[0]: wave takes at least 2.00 s at speed 1; duration = 0.5 is too short, "
        'got {"action": "wave", "duration": 0.5}',
        "profiles/x.toml: source.choreography[1]: a walk needs x_mm, where to walk to (mm, towards the image's right), "
        'got {"action": "walk"}',
    ]
