"""The built-in render effects, proved by the pixels of a real headless render: depth as a
texture, the performer's mask (or a depth band without one), sparks that follow the hand, and a
burst only where the chosen gesture happened; each performer in their user's colour."""
import numpy as np

from effects.depth_view import DepthView
from effects.gesture_burst import GestureBurst
from effects.hand_trails import HandTrails
from effects.silhouette import Silhouette
from effects.star_trail import StarTrail
from host import USER_COLOURS, DepthFrame, Frame, Hand, HandState, Side, User, user_colour
from tests.host.render.stage import SIZE as DEPTH_SIZE
from tests.host.render.stage import K, depth_image, frames_with_hand, gesture_at, lit, requires_gl, run_show

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


# -- users: one palette (host.user_colour) for every effect that colours by performer ----------

LEFT_USER, RIGHT_USER = (-500.0, 150.0, 2000.0), (500.0, 150.0, 2000.0)  # a hand of each, mm


def two_users(count: int, labels: np.ndarray | None = None, ids: tuple[int, int] = (1, 2)) -> list[Frame]:
    """Frames of two performers, user ids[0] with a hand on the left and ids[1] on the right;
    `labels` (depth-sized) as the backend's user labels."""
    out = []
    for i in range(count):
        depth = DepthFrame(depth_image(), K, frame_id=i, timestamp=i / 30)
        state = HandState.NEW if i == 0 else HandState.TRACKING
        users = tuple(User(u, state) for u in ids)
        hands = tuple(Hand(10 * u + 2, state, p, Side.RIGHT, u, extended=True)
                      for u, p in zip(ids, (LEFT_USER, RIGHT_USER)))
        out.append(Frame(i + 1, depth.capture_time, depth, hands, (), "scripted", users=users,
                         make_user_labels=None if labels is None else (lambda: labels)))
    return out


def bgr(colour: tuple[float, float, float]) -> np.ndarray:
    return np.round(np.asarray(colour[::-1]) * 255).astype(int)


def labelled_halves() -> np.ndarray:
    """User 1 in a box on the left of the depth image, user 3 on the right, nobody elsewhere."""
    labels = np.zeros((DEPTH_SIZE[1], DEPTH_SIZE[0]), np.uint8)
    labels[20:100, 10:50] = 1
    labels[20:100, 110:150] = 3
    return labels


def test_user_colours_are_distinct_and_stable():
    first = [user_colour(u) for u in range(1, len(USER_COLOURS) + 1)]
    assert len(set(first)) == len(first)
    assert min(np.abs(np.subtract(a, b)).sum() for i, a in enumerate(first) for b in first[i + 1:]) > 0.3
    assert user_colour(2) == first[1] and user_colour(2 + len(USER_COLOURS)) == first[1]


@requires_gl
def test_silhouette_colours_each_user_from_the_label_image(tmp_path):
    frames = two_users(4, labelled_halves(), ids=(1, 3))
    image, _, _ = run_show([Silhouette()], frames, tmp_path, SIZE)
    one, three = image[40:200, 20:100].reshape(-1, 3), image[40:200, 220:300].reshape(-1, 3)
    assert np.abs(one.astype(int) - bgr(user_colour(1))).max() <= 1
    assert np.abs(three.astype(int) - bgr(user_colour(3))).max() <= 1
    assert image[:, 110:210].max() == 0 and image[:30].max() == 0  # nobody: nothing drawn
    # one texture per frame: the labels were drawn, no mask was derived from them
    assert all("user_mask" not in f.__dict__ for f in frames)


@requires_gl
def test_silhouette_not_by_user_draws_every_labelled_user_in_its_colour(tmp_path):
    effect = Silhouette(Silhouette.Options(by_user=False, color=(1.0, 1.0, 1.0)))
    image, _, _ = run_show([effect], two_users(4, labelled_halves(), ids=(1, 3)), tmp_path, SIZE)
    assert np.all(image[40:200, 20:100] == 255) and np.all(image[40:200, 220:300] == 255)
    assert image[:, 110:210].max() == 0


@requires_gl
def test_hand_trails_draw_each_users_hands_in_the_users_colour(tmp_path):
    frames = two_users(6, ids=(1, 2))
    image, _, stage = run_show([HandTrails(HandTrails.Options(size=0.03))], frames, tmp_path, SIZE)
    for hand, user in ((LEFT_USER, 1), (RIGHT_USER, 2)):
        assert np.abs(lit(image, stage.to_stage(hand, frames[-1].depth)).astype(int) - bgr(user_colour(user))).max() <= 2


@requires_gl
def test_star_trail_by_user_sparks_in_the_users_colour(tmp_path):
    frames = two_users(8, ids=(1, 2))
    effect = StarTrail(StarTrail.Options(by_user=True, speed=0.01, size=0.03, rate=400))
    image, _, stage = run_show([effect], frames, tmp_path, SIZE)  # blended over, not added up to white
    for hand, channel in ((LEFT_USER, 2), (RIGHT_USER, 1)):  # user 1 red, user 2 green (BGR)
        x, y = (int(c) for c in stage.to_stage(hand, frames[-1].depth))
        patch = image[y - 15: y + 16, x - 15: x + 16].reshape(-1, 3).astype(int).sum(axis=0)
        assert patch.argmax() == channel and patch[channel] > 2 * np.delete(patch, channel).max()


@requires_gl
def test_silhouette_per_user_from_a_replayed_recording(tmp_path):
    """The labels a backend gave are recorded and the replay backend gives them back: a rehearsal
    from the file draws each user in their colour, as the live show did."""
    from backends.replay import ReplayBackend
    from host.recording import RecordingWriter
    with RecordingWriter(tmp_path / "duet.mcap") as writer:
        for frame in two_users(4, labelled_halves(), ids=(1, 3)):
            writer.write_frame(frame)
    with ReplayBackend.for_recording(tmp_path / "duet.mcap") as replay:
        frames = list(iter(replay.update, None))
    image, _, _ = run_show([Silhouette()], frames, tmp_path, SIZE)
    one, three = image[40:200, 20:100].reshape(-1, 3), image[40:200, 220:300].reshape(-1, 3)
    assert np.abs(one.astype(int) - bgr(user_colour(1))).max() <= 1
    assert np.abs(three.astype(int) - bgr(user_colour(3))).max() <= 1
    assert image[:, 110:210].max() == 0
