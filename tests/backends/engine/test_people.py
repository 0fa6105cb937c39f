"""Several people in the open engine: found, told apart, kept through a crossing, lost, recognised
on a quick return; each with their own gestures and their own pixels in the label image."""
from __future__ import annotations

import numpy as np
import pytest

from backends.engine.backend import OpenISSBackend, OpenISSNuitrackBackend
from backends.engine.people import PeopleOptions, PeopleTracker
from backends.engine.segmentation import Grid, Person, Segment, SegmentationOptions, Segmenter
from host import DepthFrame, GestureState, HandState, Intrinsics, Side
from tests.backends.engine.performer import frames, idle, walk

SIZE = {"width": 320, "height": 240}
NEAR = {"x_mm": -900, "distance_mm": 2000, "choreography": [idle(1.0), walk(900, 2.5), idle(1.0)]}
FAR = {"x_mm": 1100, "distance_mm": 3200, "height_mm": 1650, "choreography": [idle(1.0), walk(-1100, 2.5), idle(1.0)]}


@pytest.fixture(scope="module")
def crossing():
    """Two performers cross at the picture's centre, the near one (2.0 m) in front of the far one (3.2 m)."""
    return frames(performers=[NEAR, FAR], **SIZE)


@pytest.fixture(scope="module")
def gesturing():
    """A performer waves with the right hand while another, farther and to the side, raises the left."""
    wave = {"x_mm": -700, "distance_mm": 2200, "choreography": [idle(0.5), {"action": "wave", "hand": "right"}, idle(1.0)]}
    raise_ = {"x_mm": 900, "distance_mm": 3000, "choreography": [idle(1.0), {"action": "hand_raise", "hand": "left"},
                                                                   idle(1.5)]}
    return frames(performers=[wave, raise_], **SIZE)


@pytest.fixture(scope="module")
def near_child():
    """The `range` scene's first 1.5 s: a child (1.2 m tall) 0.9 m from the camera, hips and legs below
    the picture (only 0.45 m of them in view), and an adult 4.4 m away."""
    return [f for f in frames(scene="range", **SIZE) if f.timestamp < 1.5]


def run(depth_frames):
    engine = OpenISSBackend().build_engine()
    return [engine.step(f) for f in depth_frames]


def who_is_who(frame, result) -> dict[int, int]:
    """Engine user id per truth performer: the reported user whose torso is nearest theirs (within 300 mm)."""
    out = {}
    for truth in frame.truth.users:
        near = [(np.linalg.norm(np.subtract(u.joints["torso"].position, truth.body["torso"])), u.id)
                for u in result.users if u.in_view]
        d, uid = min(near, default=(np.inf, None))
        if d < 300:
            out[truth.id] = uid
    return out


def test_two_people_are_found_with_distinct_ids(crossing):
    results = run(crossing[:10])
    first = results[0]
    assert [u.state for u in first.users] == [HandState.NEW, HandState.NEW]
    assert all(u.state is HandState.TRACKING for u in results[1].users)
    ids = who_is_who(crossing[5], results[5])
    assert set(ids) == {1, 2} and len(set(ids.values())) == 2
    for u in results[5].users:
        assert {"torso", "head"} <= set(u.joints) and u.center_of_mass is not None


def test_ids_are_kept_through_a_crossing(crossing):
    results = run(crossing)
    start = who_is_who(crossing[0], results[0])
    assert len(start) == 2
    seen_both = 0
    for frame, result in zip(crossing, results):
        now = who_is_who(frame, result)
        assert all(start[k] == v for k, v in now.items()), (frame.timestamp, start, now)
        seen_both += len(now) == 2
    assert seen_both >= 0.9 * len(crossing)  # the far one is hidden only while right behind the near one
    assert who_is_who(crossing[-1], results[-1]) == start
    # the near performer crossed from the image's left to its right
    near = start[1]
    xs = [next(u.joints["torso"].position[0] for u in r.users if u.id == near) for r in (results[0], results[-1])]
    assert xs[0] < -600 and xs[1] > 600


def test_a_user_hidden_behind_another_stays_tracked_with_both_hands(crossing):
    """While the far performer is hidden, they are still a TRACKING user (joints at confidence 0 once
    unseen) with both hands held where last seen: no LOST and NEW again around a crossing (an
    OSCeleton consumer would get /lost_user)."""
    results = run(crossing)
    ids = {u.id for u in results[0].users}
    hidden, reported = 0, set()
    for result in results[1:]:
        assert {u.id for u in result.users} == ids
        assert all(u.state is HandState.TRACKING for u in result.users)
        hands = {(h.user_id, h.side) for h in result.user_hands if h.in_view}
        assert reported <= hands  # a hand once reported stays, hidden or not
        reported |= hands
        hidden += any(all(j.confidence == 0.0 for j in u.joints.values()) for u in result.users)
    assert len(reported) == 4
    assert hidden > 0  # the far one was really out of sight for a while


def test_each_users_gestures_carry_their_user_id(gesturing):
    results = run(gesturing)
    ids = who_is_who(gesturing[10], results[10])
    done = [g for r in results for g in r.gestures if g.state is GestureState.COMPLETE]
    waves = [g for g in done if g.name == "wave"]
    raises = [g for g in done if g.name == "hand_raise"]
    assert waves and all(g.user_id == ids[1] and g.side is Side.RIGHT for g in waves), done
    assert raises and all(g.user_id == ids[2] and g.side is Side.LEFT for g in raises), done
    hands = {h.id: h.user_id for r in results for h in r.hands}
    assert {hands[g.hand_id] for g in waves} == {ids[1]} and {hands[g.hand_id] for g in raises} == {ids[2]}


class Played:
    """Frames already rendered, as a source gives them."""

    def __init__(self, frames) -> None:
        self.frames = iter(frames)

    def open(self) -> None:
        pass

    def read(self):
        return next(self.frames, None)


def last_frame(cls, depth_frames):
    backend = cls(Played(depth_frames))
    backend.init()
    backend.start_hand_tracking()
    for _ in depth_frames:
        frame = backend.update()
    return frame


def test_the_label_image_gives_each_user_their_pixels(crossing):
    frame = last_frame(OpenISSBackend, crossing[:5])
    labels = frame.user_labels
    assert labels.dtype == np.uint8 and labels.shape == (frame.depth.height, frame.depth.width)
    ids = who_is_who(crossing[4], frame)
    assert set(np.unique(labels)) == {0, *ids.values()}
    for truth in crossing[4].truth.users:
        u, v, _ = frame.depth.intrinsics.world_to_depth(*truth.body["torso"])
        assert labels[int(v), int(u)] == ids[truth.id]
    assert np.array_equal(frame.user_mask, labels > 0)
    assert (labels > 0).sum() < 0.5 * labels.size  # the room is nobody


def test_nuitrack_mode_numbers_each_users_hands_as_the_adapter_does(gesturing):
    """As the Nuitrack adapter numbers them: user n's hands are 2n - 1 (left) and 2n (right)."""
    backend = OpenISSNuitrackBackend(Played(gesturing))
    backend.init()
    backend.start_hand_tracking()
    seen, ids = set(), {}
    while (frame := backend.update()) is not None:
        seen |= {(h.user_id, h.id, h.side) for h in frame.hands}
        ids = ids or who_is_who(frame.depth, frame)
    waver, raiser = ids[1], ids[2]
    assert (waver, 2 * waver, Side.RIGHT) in seen and (raiser, 2 * raiser - 1, Side.LEFT) in seen
    assert all(hid == 2 * (user - 1) + (1 if side is Side.LEFT else 2) for user, hid, side in seen), seen


# -- the people tracker alone ---------------------------------------------------------------

GRID = Grid(*(np.zeros((12, 16), np.float32) for _ in range(4)), 1.0, 1.0)


def person(x: float, z: float = 2500.0, top: float = 600.0, cols: slice = slice(0, 2)) -> Person:
    mask = np.zeros(GRID.shape, bool)
    mask[2:10, cols] = True
    return Person(Segment(mask, GRID), np.array([x, 0.0, z]), top, int(mask.sum()))


def play(tracker: PeopleTracker, scenes: list[tuple[float, list[Person]]]) -> list[list]:
    return [[(u.id, u.state) for u in tracker.update(t, people)] for t, people in scenes]


def test_a_person_unseen_is_lost_after_the_timeout_once():
    tracker = PeopleTracker(PeopleOptions(lost_timeout_s=1.0))
    out = play(tracker, [(0.0, [person(0)]), (0.1, [person(10)]), (0.5, []), (1.05, []), (1.2, []), (1.3, [])])
    assert out[:3] == [[(1, HandState.NEW)], [(1, HandState.TRACKING)], [(1, HandState.TRACKING)]]
    assert out[3] == [(1, HandState.TRACKING)]  # 0.95 s unseen: hidden, not gone
    assert out[4] == [(1, HandState.LOST)] and out[5] == []


def test_a_person_back_soon_at_the_same_place_keeps_the_id():
    tracker = PeopleTracker(PeopleOptions(lost_timeout_s=0.5, return_s=5.0))
    play(tracker, [(0.0, [person(-1000), person(1000, cols=slice(10, 12))]),
                   (0.1, [person(-1000), person(1000, cols=slice(10, 12))])])
    lost = play(tracker, [(t, [person(1000, cols=slice(10, 12))]) for t in (0.2, 0.5, 0.8)])
    assert (1, HandState.LOST) in lost[-1]
    # someone new elsewhere gets a new id (1 waits for the one who left), ...
    newcomer = play(tracker, [(1.0, [person(1000, cols=slice(10, 12)), person(0, z=4000, cols=slice(5, 7))])])
    assert (3, HandState.NEW) in newcomer[0]
    # ... the one who left, back at about the same place 2 s later, is 1 again
    back = play(tracker, [(2.8, [person(1000, cols=slice(10, 12)), person(0, z=4000, cols=slice(5, 7)),
                                 person(-900)])])
    assert (1, HandState.NEW) in back[0]


def test_a_person_back_late_or_elsewhere_is_someone_new():
    tracker = PeopleTracker(PeopleOptions(lost_timeout_s=0.5, return_s=2.0))
    play(tracker, [(0.0, [person(-1000), person(1000)]), (0.1, [person(-1000), person(1000)])])
    play(tracker, [(t, [person(1000)]) for t in (0.2, 0.5, 0.8)])
    elsewhere = play(tracker, [(1.0, [person(1000), person(-1000, z=3500, cols=slice(5, 7))])])
    assert (3, HandState.NEW) in elsewhere[0]  # 1 m deeper than where 1 left: not them
    taller = play(tracker, [(1.1, [person(1000), person(-1000, top=900)])])
    assert (4, HandState.NEW) in taller[0]  # where 1 left, but 300 mm taller: someone else
    late = play(tracker, [(t, [person(1000)]) for t in np.arange(1.4, 3.4, 0.3)] + [(3.5, [person(1000), person(-1000)])])
    assert [(3, HandState.LOST), (4, HandState.LOST)] in [[u for u in frame if u[0] in (3, 4)] for frame in late]
    # at -1000 again: 1 (lost 2.7 s ago) is forgotten; 4 (lost 1.9 s ago, stood there last) is back
    assert late[-1] == [(2, HandState.TRACKING), (4, HandState.NEW)]


def test_two_people_crossing_one_behind_the_other_keep_their_ids():
    """Walking towards each other at 1.5 m/s, the far one hidden behind the near one for 0.3 s."""
    tracker = PeopleTracker()
    ids = {}
    for k in range(60):
        t = k / 30
        near, far = person(-1500 + 1500 * t, z=2000), person(1500 - 1500 * t, z=3200, top=500)
        hidden = 0.85 <= t <= 1.15
        for u in tracker.update(t, [near] if hidden else [near, far]):
            if u.person is not None:
                ids.setdefault("near" if u.person is near else "far", set()).add(u.id)
    assert ids == {"near": {1}, "far": {2}}


def test_two_people_at_the_same_depth_keep_their_ids_by_heading():
    """At the same depth they merge into one surface as they pass (0.2 s); then each is looked for
    where they were heading, not where they were last seen apart."""
    tracker = PeopleTracker()
    ids = {}
    for k in range(60):
        t = k / 30
        a, b = person(-1500 + 1500 * t), person(1500 - 1500 * t)
        together = 0.9 <= t <= 1.1
        for u in tracker.update(t, [person(0, cols=slice(0, 4))] if together else [a, b]):
            if u.person is not None and not together:
                ids.setdefault("a" if u.person is a else "b", set()).add(u.id)
    assert ids == {"a": {1}, "b": {2}}


@pytest.mark.parametrize("max_enclosed, phantoms", [(SegmentationOptions().max_enclosed, False), (1.0, True)])
def test_the_wall_between_a_raised_arm_and_the_head_is_nobody(max_enclosed, phantoms):
    """A raised arm cuts a piece of the back wall off between itself, the head and the picture's
    edge, as tall as a person: it is surrounded by the performer, so it is background."""
    raised = frames([idle(0.3), {"action": "hand_raise", "hand": "right"}, idle(0.5)], seed=1, **SIZE)
    segmenter = Segmenter(SegmentationOptions(max_enclosed=max_enclosed))
    counts = [len(segmenter.people(f)) for f in raised]
    assert min(counts) == 1
    assert (max(counts) > 1) is phantoms, counts


def test_a_child_close_to_the_camera_is_found_at_once_though_cut_off_by_the_picture(near_child):
    results = run(near_child)
    near = [[u.id for u in r.users if u.in_view and u.joints["torso"].position[2] < 1500] for r in results]
    first = next((i for i, ids in enumerate(near) if ids), None)
    assert first is not None, "the child is never found"
    assert near_child[first].timestamp <= 0.5 and len(near[first]) == 1
    assert all(ids == near[first] for ids in near[first:])  # one user, the same id, in every frame after
    assert all(sum(u.in_view and u.joints["torso"].position[2] > 3500 for u in r.users) == 1 for r in results)


def furniture(width: int = 320, height: int = 240) -> DepthFrame:
    """A chair back 450 mm wide, 1 m away, its top 50 mm below the camera, and a desk top 300 mm
    below the camera from the picture's bottom (0.76 m away) to 2.2 m, both going on below the
    picture; nothing else."""
    k = Intrinsics.from_fov(width, height, 57.0, 43.0)
    v, u = np.mgrid[0:height, 0:width].astype(np.float64)
    xn, yn = (u - k.cx) / k.fx, (k.cy - v) / k.fy
    z = np.zeros((height, width))
    desk = -300 / np.minimum(yn, -1e-9)  # where each ray meets the desk's plane
    on_desk = (desk <= 2200) & (xn * desk >= 100) & (xn * desk <= 700)
    z[on_desk] = desk[on_desk]
    z[(xn * 1000 >= -480) & (xn * 1000 <= -30) & (yn * 1000 <= -50)] = 1000
    return DepthFrame(np.round(z).astype(np.uint16), k)


def test_furniture_cut_off_by_the_picture_is_nobody():
    """Both are person-sized but for their height in the picture (0.34 m and 0.31 m): a rule letting
    anything the picture's bottom cuts be a person from 300 mm took both. A person cut off shows a
    head on shoulders; the chair back's top is as wide as it is, the desk top is 0 mm tall in the room."""
    frame = furniture()
    assert len(Segmenter(SegmentationOptions(floor=False, min_user_height_mm=250)).people(frame)) == 2
    assert Segmenter(SegmentationOptions(floor=False)).people(frame) == []
