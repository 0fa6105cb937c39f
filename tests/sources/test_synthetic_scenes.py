"""Scenes of several synthetic performers: who is in view when, who hides whom, truth per performer."""
from __future__ import annotations

from functools import cache

import numpy as np
import pytest

from host import JOINTS, DepthFrame, Side
from host.errors import ProfileError
from host.plugins import Registry
from host.profile import parse
from host.recording import Recording
from host.recording.codec import truth_from_json, truth_to_json
from host.recording.reader import shifted_depth
from backends.truth import TruthBackend
from sources.synthetic import SyntheticOptions, SyntheticSource
from sources.synthetic.scene import offstage_x
from tests.recordings import SYNTH, record

CLEAN = {"width": 320, "height": 240, "noise": 0, "holes": 0}


def frames(**options) -> list[DepthFrame]:
    src = SyntheticSource(SyntheticOptions(**options))
    src.open()
    out = []
    while (frame := src.read()) is not None:
        out.append(frame)
    return out


@cache
def scene(name: str) -> tuple[DepthFrame, ...]:
    """A built-in scene, clean, at 320x240 (rendered once per test session)."""
    return tuple(frames(scene=name, **CLEAN))


def ids(frame: DepthFrame) -> tuple[int, ...]:
    return tuple(u.id for u in frame.truth.users)


def runs(shown) -> list[tuple[int, ...]]:
    """The successive sets of performers in view, each listed once per run."""
    out: list[tuple[int, ...]] = []
    for frame in shown:
        if not out or out[-1] != ids(frame):
            out.append(ids(frame))
    return out


def visible(frame: DepthFrame, user_id: int) -> int:
    return int(np.count_nonzero(frame.truth.user_labels == user_id))


def test_a_duet_keeps_both_performers_in_view_with_their_ids_and_truth():
    shown = scene("duet")
    assert runs(shown) == [(1, 2)]
    for frame in shown:
        first, second = frame.truth.users
        assert frame.truth.hands == first.hands and frame.truth.body == first.body
        assert first.body["torso"][2] < 2100 < 3100 < second.body["torso"][2]  # 2.0 m and 3.2 m away
    gestures = {(u.id, g.name, g.side) for f in shown for u in f.truth.users for g in u.gestures}
    assert gestures == {(1, "wave", Side.RIGHT), (1, "swipe_left", Side.RIGHT),
                        (2, "click", Side.LEFT), (2, "swipe_up", Side.LEFT)}


def test_the_duet_crosses_twice_the_near_performer_hiding_the_far_one():
    shown = scene("duet")
    hidden = [visible(f, 2) / np.median([visible(g, 2) for g in shown]) for f in shown]
    dips = [i for i in range(1, len(shown) - 1) if hidden[i] < 0.35 and hidden[i] <= min(hidden[i - 1], hidden[i + 1])]
    assert len(dips) == 2  # once each way
    for i in dips:
        frame = shown[i]
        near, far = frame.truth.users
        u, v, _ = frame.world_to_depth(far.body["torso"])
        drawn = frame.data[round(v), round(u)]
        assert abs(drawn - near.body["torso"][2]) < 400  # the far torso's pixel shows the near body (side on)
        assert frame.truth.user_labels[round(v), round(u)] == near.id
    x_near = [shown[i].truth.users[0].body["torso"][0] for i in dips]
    assert x_near[0] > -300 and x_near[1] < 300  # crossing left to right, then back
    assert abs(x_near[0]) < 300 and abs(x_near[1]) < 300  # at the picture's centre


def test_in_a_handover_one_leaves_while_the_other_enters_and_the_first_comes_back():
    shown = scene("handover")
    assert runs(shown) == [(1,), (1, 2), (2,), (1, 2), (1,)]
    enter = next(i for i, f in enumerate(shown) if 2 in ids(f))
    assert visible(shown[enter], 2) > 0  # in view means seen: the torso is inside the picture
    leave = next(i for i, f in enumerate(shown) if i > enter and 1 not in ids(f))
    assert shown[leave - 1].truth.users[0].body["torso"][0] > 1000  # left to the right...
    back = next(i for i, f in enumerate(shown) if i > leave and 1 in ids(f))
    assert shown[back].truth.users[0].body["torso"][0] > 1000  # ...and comes back from there
    full = np.median([visible(f, 1) for f in shown[:enter]])
    assert visible(shown[leave], 1) < 0.5 * full  # the torso just out: at most an arm and a side show
    assert visible(shown[leave + 15], 1) == 0  # then nothing at all
    # the first performer in view gives the single-user truth
    assert shown[leave + 5].truth.hands == shown[leave + 5].truth.users[0].hands
    assert shown[leave + 5].truth.users[0].id == 2


def test_a_trio_has_a_child_and_three_depths_and_the_child_hides_the_far_adult():
    shown = scene("trio")
    assert runs(shown) == [(1, 2, 3)]
    child, adult, far = shown[0].truth.users
    assert child.body["head"][1] < adult.body["head"][1] - 500  # a child ~1.15 m tall among adults
    assert [u.body["torso"][2] for u in (child, adult, far)] == pytest.approx([1500, 2600, 4200], abs=30)
    share = [visible(f, 3) for f in shown]
    assert min(share) < 0.5 * max(share)


def test_the_range_scene_has_a_child_at_0_9_m_and_an_adult_at_4_4_m_walking_behind_it():
    shown = scene("range")
    assert runs(shown) == [(1, 2)]
    near, far = shown[0].truth.users
    assert [near.body["torso"][2], far.body["torso"][2]] == pytest.approx([900, 4400], abs=30)
    share = np.array([visible(f, 2) for f in shown]) / np.median([visible(f, 2) for f in shown])
    assert share.min() < 0.2  # hidden behind the child
    assert {g.name for f in shown for u in f.truth.users for g in u.gestures} == {
        "wave", "swipe_right", "click", "hand_raise", "swipe_left"}


def test_a_quartet_keeps_four_people_in_view_each_mostly_seen():
    shown = scene("quartet")
    assert runs(shown) == [(1, 2, 3, 4)]
    for user_id in (1, 2, 3, 4):
        seen = [visible(f, user_id) for f in shown]
        assert min(seen) > 0.4 * max(seen)  # a tracker can find all four all the time
    assert sorted(round(u.body["torso"][2], -2) for u in shown[0].truth.users) == [1800, 2200, 3400, 4300]


@pytest.mark.parametrize("name", ["duet", "handover", "trio", "range", "quartet"])
def test_truth_hands_lie_on_their_performers_depth_unless_a_nearer_body_hides_them(name):
    """At each truth hand's pixel: that hand's surface (at most a hand's length in front of the palm
    centre), or something nearer: the performer's own body (side on, walking) or another performer."""
    on_surface = own_body = others = 0
    for frame in scene(name)[::5]:
        labels = frame.truth.user_labels
        for user in frame.truth.users:
            for side, (x, y, z) in user.hands.items():
                u, v, _ = frame.world_to_depth((x, y, z))
                u, v = round(u), round(v)
                if not (0 <= u < frame.width and 0 <= v < frame.height):
                    continue
                drawn, label = int(frame.data[v, u]), labels[v, u]
                assert label != 0 and drawn < z, (frame.timestamp, user.id, side, drawn, z)
                if label != user.id:
                    others += 1
                elif z - drawn < 150:
                    on_surface += 1
                else:
                    own_body += 1
    assert on_surface > 100
    assert own_body + others < on_surface / 3
    assert others > 0 if name != "handover" else others == 0  # the handover's performers never overlap


@pytest.mark.parametrize("name", ["duet", "trio"])
def test_every_truth_joint_lies_inside_a_drawn_body(name):
    """Each joint of host.JOINTS is inside its performer: the surface seen at its pixel is a body's
    (its own or a nearer one) and in front of the joint (side on, by up to the body's width)."""
    checked = 0
    for frame in scene(name)[::10]:
        for user in frame.truth.users:
            assert set(user.body) == set(JOINTS)
            for joint, (x, y, z) in user.body.items():
                u, v, _ = frame.world_to_depth((x, y, z))
                u, v = round(u), round(v)
                if not (0 <= u < frame.width and 0 <= v < frame.height):
                    continue
                drawn, label = int(frame.data[v, u]), frame.truth.user_labels[v, u]
                assert label != 0 and drawn < z + 5, (frame.timestamp, user.id, joint, drawn, z)
                if label == user.id:
                    assert z - drawn < 650, (frame.timestamp, user.id, joint, drawn, z)
                checked += 1
    assert checked > 200


def test_labels_are_the_performers_drawn_pixels():
    frame = scene("trio")[90]
    labels = frame.truth.user_labels
    assert labels.shape == frame.data.shape and labels.dtype == np.uint8
    room = frames(choreography=[{"action": "idle", "duration": 0.1}], **CLEAN, distance_mm=4200)[0]
    # nobody: the room; somebody: nearer than the room (the back wall is farther from the lone performer)
    assert np.array_equal(frame.data[labels == 0] > 0, room.data[labels == 0] > 0)
    assert np.all(frame.data[labels > 0] < 5600)


def test_a_lone_performer_is_user_one_and_a_looping_scene_keeps_its_ids():
    lone = frames(choreography=[{"action": "wave"}], width=160, height=120)
    assert all(ids(f) == (1,) and f.truth.users[0].hands == f.truth.hands for f in lone)
    src = SyntheticSource(SyntheticOptions(scene="handover", loop=True, speed=4.0, width=160, height=120))
    src.open()
    shown = [src.read() for _ in range(int(2 * src.length * src.fps) + 5)]
    assert runs(shown) == [(1,), (1, 2), (2,), (1, 2), (1,), (1, 2), (2,), (1, 2), (1,)]


def test_the_truth_backend_reports_each_performer_as_a_user_with_its_label_image():
    src = SyntheticSource(SyntheticOptions(scene="handover", width=160, height=120))
    with TruthBackend(src) as backend:
        backend.start_hand_tracking()
        tracked = []
        while (frame := backend.update()) is not None:
            tracked.append(frame)
    states = {1: [], 2: []}
    for frame in tracked:
        for user in frame.users:
            if not states[user.id] or states[user.id][-1] != user.state.value:
                states[user.id].append(user.state.value)
        truth = frame.depth.truth
        assert [u.id for u in frame.users if u.in_view] == [u.id for u in truth.users]
        assert frame.user_labels is truth.user_labels
        assert all(h.user_id == truth.users[0].id for h in frame.hands)
    assert states == {1: ["new", "tracking", "lost", "new", "tracking"], 2: ["new", "tracking", "lost"]}
    first = tracked[0].users[0]
    assert first.joints["right_hand"].position == tracked[0].depth.truth.hands[Side.RIGHT]
    assert first.center_of_mass[1] < first.joints["torso"].position[1]  # between the torso and the hips


def test_performers_come_from_a_profile_with_their_own_choreography_files(tmp_path):
    registry = Registry()
    registry.register("backends", TruthBackend, "test")
    registry.register("sources", SyntheticSource, "test")
    (tmp_path / "steps.toml").write_text('[[steps]]\naction = "wave"\nhand = "left"\n')
    text = ('backend = "truth"\n[source]\nname = "synthetic"\n'
            f'[[source.performers]]\nheight_mm = 1200\ndistance_mm = 1500\nx_mm = {-offstage_x(1500):.0f}\n'
            'choreography = [{action = "walk", x_mm = 0, duration = 3.0}]\n'
            '[[source.performers]]\ndistance_mm = 3500\nchoreography_file = "steps.toml"\n')
    profile = parse(text, str(tmp_path / "p.toml"), tmp_path, registry)
    src = SyntheticSource(profile.source.options)
    src.open()
    shown = []
    while (frame := src.read()) is not None:
        shown.append(frame)
    assert runs(shown) == [(2,), (1, 2)]  # the child walks in from beyond the picture's left edge
    assert {g.name for f in shown for u in f.truth.users if u.id == 2 for g in u.gestures} == {"wave"}


def test_scene_options_that_belong_to_performers_are_refused_with_where_to_put_them(tmp_path):
    registry = Registry()
    registry.register("backends", TruthBackend, "test")
    registry.register("sources", SyntheticSource, "test")
    for extra, expected in (('scene = "duet"\ndistance_mm = 2000\n', "distance_mm: with a scene or performers"),
                            ('scene = "sextet"\n', "expected 'duet', 'handover', 'trio', 'range' or 'quartet'"),
                            ('[[source.performers]]\nx_mm = 0\n', "a choreography or a choreography_file")):
        with pytest.raises(ProfileError) as caught:
            parse(f'backend = "truth"\n[source]\nname = "synthetic"\n{extra}', "p.toml", tmp_path, registry)
        assert expected in "\n".join(caught.value.lines), caught.value.lines


def test_a_recorded_duet_keeps_every_performers_truth(tmp_path):
    """`issv record` of a duet: the truth read back has both users, as the source gave them."""
    path = record(tmp_path, seconds=5.0, scene="duet")
    live = frames(scene="duet", **SYNTH)
    with Recording(path) as rec:
        back = [f.depth for f in rec.frames()]
    assert len(back) >= 150
    for recorded, shown in zip(back, live):
        assert recorded.truth.users == shown.truth.users and len(shown.truth.users) == 2
        assert recorded.truth.hands == shown.truth.hands
    assert any(u.gestures for f in back for u in f.truth.users if u.id == 2)


def test_a_looped_recording_shifts_every_performers_gesture_intervals():
    depth = next(f for f in scene("duet") if f.truth.users[1].gestures)
    later = shifted_depth(depth, 20.0, 0.0)
    assert later.truth.users[1].gestures[0].start == depth.truth.users[1].gestures[0].start + 20.0
    assert later.truth.users[1].hands == depth.truth.users[1].hands


def test_recordings_without_users_still_read():
    """Recordings of one performer, and those made before scenes, have no `users` key."""
    old = {"hands": {"right": [1.0, 2.0, 3.0]}, "gestures": [], "body": {"torso": [0.0, 0.0, 2000.0]}}
    truth = truth_from_json(old)
    assert truth.users == () and truth.hands[Side.RIGHT] == (1.0, 2.0, 3.0)
    assert truth_to_json(truth) == old
