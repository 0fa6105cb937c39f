"""Where things land: a hand trail drawn where the hand is, through the keystone and the
calibration, proved by the pixels of a real headless render."""
import numpy as np

from effects.hand_trails import HandTrails
from host.render.calibration import apply, keystone_matrix
from tests.host.render.stage import K, frames_with_hand, lit, requires_gl, run_show

KEYSTONE = [(0.25, 0.05), (0.95, 0.25), (0.8, 0.95), (0.05, 0.7)]
SIZE = (320, 240)
PATH = [(-700.0 + 25 * i, 400.0 - 10 * i, 2000.0) for i in range(16)]  # right hand, mm, upper left


def trail_effect():
    return HandTrails(HandTrails.Options(by_user=False, colors=[(0.0, 1.0, 0.0)], size=0.03))


def expected(stage, frame, position, keystone=None):
    x, y = stage.to_stage(position, frame.depth)
    if keystone is None:
        return x, y
    return tuple(apply(keystone_matrix(keystone, SIZE), [(x, y)])[0])


@requires_gl
def test_the_trail_head_lands_on_the_hand_after_the_keystone(tmp_path):
    frames = frames_with_hand(PATH)
    image, show, stage = run_show([trail_effect()], frames, tmp_path, SIZE, keystone=KEYSTONE)
    head = expected(stage, frames[-1], PATH[-1], KEYSTONE)
    b, g, r = lit(image, head)
    assert g > 200 and r < 60 and b < 60, f"no green hand at {head}: {(b, g, r)}"
    # Without the keystone the head would be elsewhere; that spot is dark here.
    unwarped = expected(stage, frames[-1], PATH[-1])
    assert np.hypot(unwarped[0] - head[0], unwarped[1] - head[1]) > 15
    assert lit(image, unwarped, 0)[1] < 40
    # The trail: earlier positions are lit too (dimmer), a far corner is not.
    earlier = expected(stage, frames[-8], PATH[-8], KEYSTONE)
    assert lit(image, earlier, 2)[1] > 40
    assert image[5:20, 150:170].max() < 30


@requires_gl
def test_a_calibration_moves_the_hand_to_where_it_says(tmp_path):
    # depth pixels -> stage pixels: scale 2, mirrored left-right, 5 px down (a 320x240 stage).
    calibration = [[-2.0, 0.0, 320.0], [0.0, 2.0, 5.0], [0.0, 0.0, 1.0]]
    frames = frames_with_hand(PATH)
    image, show, stage = run_show([trail_effect()], frames, tmp_path, SIZE, calibration=calibration)
    u, v, _ = K.world_to_depth(*PATH[-1])
    head = (320 - 2 * u, 2 * v + 5)
    assert stage.to_stage(PATH[-1], frames[-1].depth) == (head[0], head[1])
    assert lit(image, head)[1] > 200
    stretched = (u * SIZE[0] / 160, v * SIZE[1] / 120)  # where it would be without the calibration
    assert lit(image, stretched, 0)[1] < 40


@requires_gl
def test_lost_hands_lose_their_trail(tmp_path):
    frames = frames_with_hand(PATH[:6])
    last = frames[-1]
    from dataclasses import replace
    frames.append(replace(last, seq=last.seq + 1, hands=()))
    image, _, _ = run_show([trail_effect()], frames, tmp_path, SIZE)
    assert image.max() < 30
