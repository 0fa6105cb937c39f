"""One user's skeleton from depth (skeleton.py): both hands all the time, resting ones measured,
one id per side through down-and-up, joints with the performer's sides; on synthetic performers
(truth hands and body) and, where ISSV_DATA is set, on real Kinect clips (UTD-MHAD)."""
from __future__ import annotations

import glob
import os
from pathlib import Path

import numpy as np
import pytest

from backends.engine.backend import OpenISSBackend, OpenISSNiteBackend
from backends.engine.tracker import HandTracker
from host import JOINTS, GestureState, HandState, Side
from sources.clip import Clip
from tests.backends.engine.performer import WAVE_THEN_REST, frames
from tests.backends.engine.test_backends import play

UP_DOWN_UP = [{"action": "idle", "duration": 0.5}, {"action": "hand_raise", "hand": "right"},
              {"action": "idle", "duration": 0.8}, {"action": "hand_raise", "hand": "right"},
              {"action": "idle", "duration": 0.5}]


@pytest.fixture(scope="module")
def up_down_up():
    return frames(UP_DOWN_UP)


def track(depth_frames):
    tracker = HandTracker()
    return [tracker.process(f) for f in depth_frames]


def raised(f, side: Side = Side.RIGHT) -> bool:
    """The truth hand above the shoulders: extended by any measure."""
    return f.truth.hands[side][1] > f.truth.body[f"{side.value}_shoulder"][1]


def test_both_hands_every_frame_one_id_per_side_through_down_and_up(up_down_up):
    results = track(up_down_up)
    ups = [i for i, f in enumerate(up_down_up) if raised(f)]
    assert ups and max(np.diff(ups)) > 10, "the choreography raises the hand twice with a rest between"
    for f, r in zip(up_down_up, results):
        assert sorted(h.side.value for h in r.user_hands) == ["left", "right"]
    ids = {h.side: set() for h in results[0].user_hands}
    for r in results:
        for h in r.user_hands:
            ids[h.side].add(h.id)
    assert all(len(v) == 1 for v in ids.values()) and ids[Side.LEFT] != ids[Side.RIGHT], ids
    assert [h.state for h in results[0].user_hands] == [HandState.NEW, HandState.NEW]
    assert all(h.state in (HandState.TRACKING, HandState.TOUCHING_FOV) for r in results[1:] for h in r.user_hands)


def test_extended_flag_follows_the_arm(up_down_up):
    results = track(up_down_up)
    right = [(f, next(h for h in r.user_hands if h.side is Side.RIGHT)) for f, r in zip(up_down_up, results)]
    up = [h.extended for f, h in right if raised(f)]
    # at rest: the truth hand at least 400 mm below the shoulder line
    down = [h.extended for f, h in right if f.truth.hands[Side.RIGHT][1] < f.truth.body["right_shoulder"][1] - 400]
    assert up and down
    assert np.mean(up) > 0.9 and not any(down)
    assert not any(h.extended for r in results for h in r.user_hands if h.side is Side.LEFT)


def test_resting_hands_are_found_in_the_depth_near_the_truth(up_down_up):
    """The hand at the lower end of the hanging arm: beside the hip within a few cm; the synthetic
    truth is the palm centre, about 100 mm above where the depth ends the arm."""
    errors, measured = [], []
    for f, r in zip(up_down_up, track(up_down_up)):
        for h in r.user_hands:
            if not h.extended:
                errors.append(np.subtract(h.position, f.truth.hands[h.side]))
                measured.append(h.confidence > 0)  # 0: not seen this frame, held where it was
    e = np.array(errors)
    assert len(e) > len(up_down_up) and np.mean(measured) > 0.9
    assert np.median(np.hypot(e[:, 0], e[:, 2])) < 50
    assert np.median(np.abs(e[:, 1])) < 150


@pytest.mark.parametrize("mirrored", [True, False])
def test_joints_are_named_from_the_performers_point_of_view(mirrored):
    depth = frames(WAVE_THEN_REST[:1], mirrored=mirrored)
    results = track(depth)
    f, r = depth[-1], results[-1]
    assert set(r.joints) <= set(JOINTS)
    assert {"head", "neck", "torso", "left_shoulder", "right_shoulder", "left_hand", "right_hand"} <= set(r.joints)
    for name in ("head", "torso", "left_shoulder", "right_shoulder"):
        assert np.linalg.norm(np.subtract(r.joints[name].position, f.truth.body[name])) < 150, name
        assert 0 <= r.joints[name].confidence <= 1
    for side in (Side.LEFT, Side.RIGHT):
        hand = r.joints[f"{side.value}_hand"].position
        assert np.hypot(hand[0] - f.truth.hands[side][0], hand[2] - f.truth.hands[side][2]) < 80
    assert r.center_of_mass is not None and abs(r.center_of_mass[1] - f.truth.body["torso"][1]) < 250


def test_elbows_only_where_the_depth_shows_the_arm(up_down_up):
    results = track(up_down_up)
    elbows = [r.joints["right_elbow"].position for r in results if "right_elbow" in r.joints]
    assert len(elbows) > 0.5 * len(results)
    for r in results:
        if "right_elbow" in r.joints:
            shoulder, hand = (np.array(r.joints[n].position) for n in ("right_shoulder", "right_hand"))
            elbow = np.array(r.joints["right_elbow"].position)
            assert 150 < np.linalg.norm(elbow - shoulder) < 450 and 150 < np.linalg.norm(elbow - hand) < 450


def test_openiss_reports_both_hands_and_names_the_gesture_by_its_hand(up_down_up):
    out = play(OpenISSBackend, up_down_up)
    assert all(len(f.hands) == 2 for f in out)
    done = [g for f in out for g in f.gestures if g.state is GestureState.COMPLETE]
    assert done
    for f in out:
        for g in f.gestures:
            assert g.hand_id in {h.id for h in f.hands if h.side is g.side}


def test_a_focused_hand_is_not_lost_when_it_drops_to_rest():
    wave = frames(WAVE_THEN_REST)
    out = play(OpenISSNiteBackend, wave)
    focus = next(i for i, f in enumerate(out) for g in f.gestures if g.state is GestureState.COMPLETE)
    after = out[focus:]
    ids = {h.id for f in after for h in f.hands}
    assert len(ids) == 1 and all(len(f.hands) == 1 and f.hands[0].in_view for f in after)
    assert not after[-1].hands[0].extended, "the waving hand came down and is still reported"


DATA = os.environ.get("ISSV_DATA")
CLIPS = sorted(glob.glob(str(Path(DATA or "-") / "utd-mhad-dev" / "clips" / "*_s[1-4]_t1_*.npz")))
SCORED = {"wave", "swipe_left", "clap", "walk", "squat", "arm_curl"}


@pytest.mark.skipif(not CLIPS, reason="needs ISSV_DATA with utd-mhad-dev/clips (real Kinect clips)")
def test_real_clips_every_hand_found_near_the_kinect_skeleton():
    """score.py's figure over every truth hand, resting ones included, against the skeleton two
    frames earlier (it runs ahead of its depth)."""
    dist = []
    for path in [c for c in CLIPS if Path(c).stem.split("_", 3)[-1] in SCORED]:
        clip = Clip(path)
        tracker = HandTracker()
        for i in range(len(clip)):
            r = tracker.process(clip.frame(i, i))
            if i < 2:
                continue
            reported = [h.position for h in r.user_hands if h.in_view]
            for p in clip.hands[i - 2]:
                dist.append(min((np.linalg.norm(np.subtract(q, p)) for q in reported), default=np.inf))
    dist = np.array(dist)
    found = dist < 250
    assert found.mean() >= 0.9, found.mean()
    assert np.median(dist[found]) <= 80
