"""The built-in render effects, proved by the pixels of a real headless render: depth as a
texture, the performer's mask (or a depth band without one), sparks that follow the hand, and a
burst only where the chosen gesture happened."""
import numpy as np

from effects.depth_view import DepthView
from effects.gesture_burst import GestureBurst
from effects.silhouette import Silhouette
from effects.star_trail import StarTrail
from tests.host.render.stage import SIZE as DEPTH_SIZE
from tests.host.render.stage import frames_with_hand, gesture_at, lit, requires_gl, run_show

SIZE = (320, 240)
HAND = (-300.0, 200.0, 2000.0)
BOX = (slice(44, 216), slice(124, 196))  # inside the performer box, in stage pixels (x2)


@requires_gl
def test_depth_view_shows_the_depth_image_stretched_over_the_stage(tmp_path):
    image, _, _ = run_show([DepthView(DepthView.Options(near_mm=500, far_mm=4500))], frames_with_hand([HAND]), tmp_path, SIZE)
    inside = image[BOX]
    expected = round(255 * (1 - 0.85 * (2500 - 500) / 4000))  # the gray map at 2.5 m
    assert np.all(np.abs(inside.astype(int) - expected) <= 2)
    assert image[:, :110].max() == 0  # no reading: transparent over the black stage


@requires_gl
def test_depth_view_turbo_is_coloured(tmp_path):
    image, _, _ = run_show([DepthView(DepthView.Options(colormap="turbo"))], frames_with_hand([HAND]), tmp_path, SIZE)
    b, g, r = image[120, 160].astype(int)
    assert max(b, g, r) - min(b, g, r) > 60


@requires_gl
def test_silhouette_uses_the_backends_mask_when_there_is_one(tmp_path):
    mask = np.zeros((DEPTH_SIZE[1], DEPTH_SIZE[0]), bool)
    mask[10:40, 10:40] = True  # deliberately not where the depth box is
    effect = Silhouette(Silhouette.Options(color=(1.0, 0.0, 0.0)))
    image, _, _ = run_show([effect], frames_with_hand([HAND], mask=mask), tmp_path, SIZE)
    assert tuple(image[50, 50]) == (0, 0, 255)
    assert image[BOX].max() == 0


@requires_gl
def test_silhouette_falls_back_to_a_depth_band(tmp_path):
    inside = Silhouette(Silhouette.Options(color=(0.0, 1.0, 0.0), near_mm=2000, far_mm=3000))
    image, _, _ = run_show([inside], frames_with_hand([HAND]), tmp_path, SIZE)
    assert np.all(image[BOX] == (0, 255, 0)) and image[:, :110].max() == 0
    outside = Silhouette(Silhouette.Options(near_mm=500, far_mm=2000))
    assert run_show([outside], frames_with_hand([HAND]), tmp_path, SIZE)[0].max() == 0


@requires_gl
def test_star_trail_sparks_stream_from_the_hand(tmp_path):
    frames = frames_with_hand([HAND] * 8)
    image, _, stage = run_show([(StarTrail(StarTrail.Options(speed=0.02, size=0.03, rate=400)), "add", 1.0)], frames, tmp_path, SIZE)
    x, y = stage.to_stage(HAND, frames[-1].depth)
    lit_pixels = np.argwhere(image.max(axis=2) > 40)
    assert len(lit_pixels) > 20
    distance = np.hypot(lit_pixels[:, 1] - x, lit_pixels[:, 0] - y)
    assert np.median(distance) < 30  # the sparks stay around the hand
    assert image[200:, 250:].max() == 0


@requires_gl
def test_gesture_burst_fires_only_for_its_gesture_where_it_happened(tmp_path):
    gestures = {3: [gesture_at("swipe_left", (300.0, -200.0, 2000.0)), gesture_at("wave", HAND)]}
    frames = frames_with_hand([HAND] * 6, gestures)
    effect = GestureBurst(GestureBurst.Options(gesture="wave", color=(1.0, 1.0, 1.0), life=3.0, speed=0.05))
    image, _, stage = run_show([effect], frames, tmp_path, SIZE)
    wave = stage.to_stage(HAND, frames[-1].depth)
    swipe = stage.to_stage((300.0, -200.0, 2000.0), frames[-1].depth)
    near = lambda xy: image[int(xy[1]) - 25: int(xy[1]) + 25, int(xy[0]) - 25: int(xy[0]) + 25]
    assert near(wave).max() > 60
    assert near(swipe).max() == 0
    assert lit(image, (5, 5), 3).max() == 0


def test_gesture_burst_checks_the_gesture_name():
    import pytest
    with pytest.raises(ValueError, match="expected any or one of"):
        GestureBurst.Options(gesture="wavy")
