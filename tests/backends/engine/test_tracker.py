"""The depth hand tracker on rendered synthetic depth (floor, back wall, sensor noise) with truth."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from backends.engine.geometry import KINECT_V1, to_geometry
from backends.engine.hands import Candidate
from backends.engine.segmentation import SegmentationOptions
from backends.engine.smoothing import OneEuroFilter, SmoothingOptions
from backends.engine.tracker import HandTracker, TrackerOptions
from host import DepthFrame, HandState, Intrinsics, Side
from tests.backends.engine.performer import SWIPE, WAVE_THEN_REST, frames


@pytest.fixture(scope="module")
def wave() -> list[DepthFrame]:
    return frames(WAVE_THEN_REST)


def run(depth_frames, options=None):
    tracker = HandTracker(options)
    return [tracker.process(f) for f in depth_frames]


def waving(f: DepthFrame) -> bool:
    return any(g.name == "wave" for g in f.truth.gestures)


def test_user_and_body_found_from_the_first_frame_despite_floor_and_wall(wave):
    result = HandTracker().process(wave[0])
    truth = wave[0].truth.body
    assert result.body, "no user found on the first frame"
    assert np.linalg.norm(np.subtract(result.body["torso"], truth["torso"])) < 150
    assert np.linalg.norm(np.subtract(result.body["head"], truth["head"])) < 150
    mask = result.full_mask(wave[0])
    assert mask.shape == wave[0].data.shape
    # Neither the floor nor the back wall is part of the user: every user pixel is near the performer.
    v, u = np.nonzero(mask)
    z = wave[0].data[v, u].astype(float)
    assert np.all(np.abs(z - truth["torso"][2]) < 900)
    assert mask.sum() < 0.25 * mask.size


def test_waving_hand_tracked_with_one_id_on_the_performers_right(wave):
    results = run(wave)
    ids, errors = set(), []
    for f, r in zip(wave, results):
        if not waving(f):
            continue
        truth = np.array(f.truth.hands[Side.RIGHT])
        near = [h for h in r.hands if np.linalg.norm(np.subtract(h.position, truth)) < 250]
        if near:
            ids.add(near[0].id)
            errors.append(np.linalg.norm(np.subtract(near[0].position, truth)))
            assert near[0].side is Side.RIGHT
    assert len(errors) > 0.8 * sum(waving(f) for f in wave), "the waving hand was missed in many frames"
    assert len(ids) == 1, f"the waving hand changed id: {ids}"
    assert np.median(errors) < 100


def test_sides_are_the_performers_whatever_the_mirroring():
    unmirrored = frames(WAVE_THEN_REST[:2], mirrored=False)
    results = run(unmirrored)
    sides = {h.side for r in results for h in r.hands}
    xs = [h.position[0] for r in results for h in r.hands]
    assert sides == {Side.RIGHT}
    assert np.median(xs) < 0, "unmirrored, the performer's right hand is on the image's left (-x)"


def test_states_new_then_tracking_then_lost_once_after_the_timeout(wave):
    options = TrackerOptions(lost_timeout_s=0.3)
    tracker = HandTracker(options)
    history: dict[int, list[tuple[float, HandState]]] = {}
    for f in wave:
        for h in tracker.process(f).hands:
            history.setdefault(h.id, []).append((f.timestamp, h.state))
    wave_id = max(history, key=lambda i: len(history[i]))
    states = [s for _, s in history[wave_id]]
    assert states[0] is HandState.NEW and HandState.NEW not in states[1:]
    assert HandState.TRACKING in states
    assert states.count(HandState.LOST) == 1 and states[-1] is HandState.LOST
    seen = [t for t, s in history[wave_id] if s is not HandState.LOST]
    lost_at = history[wave_id][-1][0]
    assert lost_at - seen[-1] >= 0.3 - options.hold_s  # a missed hand is still reported for hold_s


def extended(f: DepthFrame, side: Side) -> bool:
    """The truth hand is out of its rest (score.py's rule): in front of the spine, beside it or
    above the head."""
    p, spine, head = f.truth.hands[side], f.truth.body["torso"], f.truth.body["head"]
    return spine[2] - p[2] > 200 or abs(p[0] - spine[0]) > 350 or p[1] > head[1]


def test_one_steady_hand_per_arm_through_a_one_handed_show():
    """The right hand waves, swipes both ways and clicks, resting between: an effect drawing a
    point per hand sees that hand come once per time it leaves its rest, nowhere else (not at the
    elbow sticking out during a swipe, never two hands on one arm), without flickering lost/new."""
    show = frames([{"action": "idle", "duration": 0.5}, {"action": "wave"}, {"action": "swipe_left"},
                   {"action": "swipe_right"}, {"action": "click"}, {"action": "idle", "duration": 0.5}])
    tracker = HandTracker()
    shown: set[int] = set()
    appearances = two_on_one_side = phantoms = reported = found = 0
    for f in show:
        live = [h for h in tracker.process(f).hands if h.state not in (HandState.LOST, HandState.ABSENT)]
        ids = {h.id for h in live}
        appearances += len(ids - shown)  # what an effect sees as "hand N new"
        shown = ids
        sides = [h.side for h in live]
        two_on_one_side += len(sides) != len(set(sides))
        truth = [np.array(p) for p in f.truth.hands.values()]
        phantoms += sum(min(np.linalg.norm(np.subtract(h.position, p)) for p in truth) > 150 for h in live)
        reported += len(live)
        right = np.array(f.truth.hands[Side.RIGHT])
        near = any(np.linalg.norm(np.subtract(h.position, right)) < 250 for h in live)
        found += extended(f, Side.RIGHT) and near
    outings = sum(extended(f, Side.RIGHT) and not extended(g, Side.RIGHT) for g, f in zip(show, show[1:]))
    assert found > 0.8 * sum(extended(f, Side.RIGHT) for f in show), "the extended hand was often missed"
    assert two_on_one_side == 0, f"two hands on one arm in {two_on_one_side} frames"
    assert appearances <= outings, f"{appearances} hand appearances, the hand left its rest {outings} times"
    assert phantoms <= 0.03 * reported, f"{phantoms} of {reported} reported hands far from any hand"


def test_touching_fov_when_the_image_edge_cuts_the_hand():
    swipe = frames(SWIPE)
    # The frame where the right hand is farthest out to the image's right, cut just inside the hand.
    best = max(swipe, key=lambda f: f.truth.hands[Side.RIGHT][0])
    u, _, _ = best.world_to_depth(best.truth.hands[Side.RIGHT])
    cut = int(u)
    cropped = DepthFrame(np.ascontiguousarray(best.data[:, :cut]), best.intrinsics, 1, best.timestamp,
                         mirrored=best.mirrored, truth=best.truth)
    whole = HandTracker().process(best)
    assert any(h.state is HandState.NEW for h in whole.hands)
    tracker = HandTracker()  # a cut hand is weaker evidence: it may need a second frame to be a hand
    edge = [tracker.process(replace(cropped, timestamp=best.timestamp + k / 30)) for k in range(3)]
    assert edge[-1].hands, "the cut hand must still be reported"
    assert any(h.state is HandState.TOUCHING_FOV for h in edge[-1].hands), [h.state for h in edge[-1].hands]


@pytest.mark.parametrize("size", [(320, 240), (640, 480)])
def test_any_resolution_gives_the_same_world_positions(size):
    sub = frames(WAVE_THEN_REST[:2], width=size[0], height=size[1])
    results = run(sub)
    errors = []
    for f, r in zip(sub, results):
        if waving(f):
            truth = np.array(f.truth.hands[Side.RIGHT])
            d = [np.linalg.norm(np.subtract(h.position, truth)) for h in r.hands]
            if d and min(d) < 250:
                errors.append(min(d))
    assert len(errors) > 0.8 * sum(waving(f) for f in sub)
    assert np.median(errors) < 100


def test_background_already_removed_is_the_easy_case():
    sub = frames(WAVE_THEN_REST[:2], background="none")
    results = run(sub)
    assert all(r.body for r in results)
    assert sum(bool(r.hands) for r, f in zip(results, sub) if waving(f)) > 0.8 * sum(waving(f) for f in sub)


def test_empty_scene_has_no_user_and_no_hands():
    empty = DepthFrame(np.full((240, 320), 4000, np.uint16), Intrinsics.from_fov(320, 240, 57, 43))
    result = HandTracker().process(empty)
    assert result.hands == () and result.body == {} and result.full_mask(empty) is None


def test_one_euro_smooths_rest_and_follows_motion():
    rng = np.random.default_rng(0)
    t = np.arange(60) / 30
    still = np.stack([rng.normal(0, 5, 60), np.zeros(60), np.full(60, 2000.0)], axis=1)  # 5 mm jitter
    f = OneEuroFilter(SmoothingOptions())
    smoothed = np.array([f(ti, p) for ti, p in zip(t, still)])
    assert smoothed[10:, 0].std() < 0.75 * still[10:, 0].std()
    moving = np.stack([1500 * t, np.zeros(60), np.full(60, 2000.0)], axis=1)  # 1.5 m/s
    lag = {}
    for beta in (0.0, 0.03):
        f = OneEuroFilter(SmoothingOptions(beta=beta))
        out = np.array([f(ti, p) for ti, p in zip(t, moving)])
        lag[beta] = moving[-1, 0] - out[-1, 0]
    assert lag[0.03] < 0.5 * lag[0.0]
    off = OneEuroFilter(SmoothingOptions(enabled=False))
    assert np.allclose([off(ti, p) for ti, p in zip(t, still)], still)


def test_kinect_v1_geometry_keeps_world_positions(wave):
    small = frames(WAVE_THEN_REST[:1], width=320, height=240)[0]
    big = to_geometry(small, *KINECT_V1)
    assert (big.width, big.height) == (640, 480) and big.intrinsics == KINECT_V1[1]
    # Any reading of the resampled image lies on the ray of the same reading in the original.
    v, u = 300, 330
    z = big.data[v, u]
    assert z > 0
    x, y, _ = big.depth_to_world(u, v, z)
    su, sv, _ = small.world_to_depth((x, y, z))
    assert abs(small.data[int(round(sv)), int(round(su))] - int(z)) < 60
    assert to_geometry(big, *KINECT_V1) is big


@pytest.mark.parametrize("covered", [False, True])
def test_a_forearm_across_the_face_does_not_move_the_body(covered):
    """A swipe passes in front of the face: the top of the head is hidden behind the forearm, and
    a crown read below it would drop the shoulder line and the torso (hands judged against a body
    that jumps make gestures of nothing). The body stays put; an uncovered head still counts."""
    standing = frames([{"action": "idle", "duration": 1.0}], background="none")
    k = standing[0].intrinsics
    head = np.array(standing[0].truth.body["head"])
    u, v, _ = k.world_to_depth(*head)
    z = head[2] - 450  # a forearm 45 cm in front of the face, from its centre to 200 mm above it
    top, bottom = (int(k.world_to_depth(head[0], head[1] + dy, head[2])[1]) for dy in (200, 0))
    half = int(200 * k.fx / head[2])
    tracker = HandTracker()
    torso = []
    for i, f in enumerate(standing):
        data = f.data.copy()
        if i >= len(standing) // 2:
            # uncovered: the same forearm held 300-400 mm above the head's centre, clear of the head
            rows = slice(top, bottom) if covered else slice(top - (bottom - top), top - (bottom - top) // 2)
            data[rows, int(u) - half:int(u) + half] = int(z)
        torso.append(tracker.process(replace(f, data=data)).body["torso"][1])
    before, during = np.array(torso[: len(torso) // 2]), np.array(torso[len(torso) // 2:])
    assert abs(float(np.median(during) - np.median(before))) < 25


@pytest.mark.parametrize("lost, period", [("rows", 4), ("columns", 4), ("rows", 2)])
def test_lines_of_missing_readings_do_not_cut_the_user_apart(wave, lost, period):
    """Every fourth or second row (or column) of the internal grid without readings, as a rescaled or
    interlaced source gives: the user is still one surface, with the body where it is."""
    step = 640 // SegmentationOptions().grid_width
    v, u = np.indices(wave[0].data.shape) // step
    holes = (v if lost == "rows" else u) % period == period - 1
    sparse = [replace(f, data=np.where(holes, 0, f.data).astype(np.uint16)) for f in wave[:30]]
    results = run(sparse)
    assert all(r.body for r in results)
    for r, f in zip(results, sparse):
        assert np.linalg.norm(np.subtract(r.body["torso"], f.truth.body["torso"])) < 150
    assert sum(bool(r.hands) for r, f in zip(results, sparse) if waving(f)) > 0.8 * sum(waving(f) for f in sparse)


def test_a_hand_held_through_a_dropout_is_reported_but_not_seen(wave):
    """Missed for a frame, a tracked hand is still reported where it was last seen (effects do not
    see it flicker), but it is not among the hands found in that frame: the recogniser must not
    take its standing still for a stop."""
    tracker = HandTracker()
    results = [tracker.process(f) for f in wave[:40]]
    last = results[-1]
    assert last.hands and {h.id for h in last.hands} == last.seen
    blank = replace(wave[40], data=np.zeros_like(wave[40].data))  # nothing seen at all
    held = tracker.process(blank)
    assert [h.id for h in held.hands] == [h.id for h in last.hands] and held.seen == frozenset()
    assert [h.position for h in held.hands] == [h.position for h in last.hands]


def test_a_fast_hand_is_matched_from_where_it_was_last_found_not_only_from_its_smoothed_position():
    """The reported position is smoothed and lags a fast hand (a whole-arm wave swinging back): the
    hand found next may be out of the gate from there yet within it of where it was last found. It is
    the same hand, not a new one (UTD-MHAD's whole-arm waves lost their last swing so)."""
    tracker = HandTracker()
    o = tracker.options
    dt = 1 / 30
    gate = o.match_slack_mm + o.max_speed_mm_s * dt
    found = np.array([0.0, 300.0, 2000.0])
    shoulder = np.array([150.0, 300.0, 2000.0])
    track = tracker._birth(0.0, Candidate(found, 600.0, False, shoulder, 1.0), Side.RIGHT)
    track.position = found - np.array([100.0, 0.0, 0.0])  # smoothed: 100 mm behind a hand moving right
    tracker._tracks.append(track)
    next_frame = Candidate(found + np.array([gate - 10.0, 0.0, 0.0]), 600.0, False, shoulder, 1.0)
    assert tracker._match(dt, [next_frame], None, True) == {track: next_frame}
    too_far = replace(next_frame, position=found + np.array([gate + 10.0, 0.0, 0.0]))
    assert tracker._match(dt, [too_far], None, True) == {}


def test_a_hand_seen_apart_from_its_arm_and_farther_out_is_the_tracked_hand_not_a_second_one():
    """A whole arm swinging across the face: the depth shows the hand cut off from its arm (joined to the
    body nowhere without a depth jump, so on the far side of the spine it looks like the other arm's)
    and the forearm nearer the hand's last find. The hand keeps its id and moves on; the forearm is not
    a hand. Joined to the body, the same find is the other arm's hand."""
    def frame(loose: bool):
        tracker = HandTracker()
        torso, shoulder = np.array([0.0, 0.0, 2100.0]), np.array([150.0, 300.0, 2000.0])
        found = np.array([40.0, 300.0, 2000.0])
        first = tracker._update_tracks(0.0, [Candidate(found, 420.0, False, shoulder, 1.0)], torso, True)
        forearm = Candidate(found + np.array([-20.0, -20.0, 0.0]), 380.0, False, shoulder, 1.0)
        hand = Candidate(found + np.array([-170.0, 0.0, 0.0]), 430.0, False, found + np.array([-170.0, 0.0, 0.0]),
                         1.0, loose=loose)
        return first, tracker._update_tracks(1 / 30, [forearm, hand], torso, True)
    first, after = frame(loose=True)
    assert [h.id for h in after] == [first[0].id] and after[0].position[0] < first[0].position[0] - 50
    _, after = frame(loose=False)
    assert len(after) == 2


def test_a_piece_cut_off_from_a_tracked_arm_next_to_its_hand_is_no_second_hand():
    """A whole arm swinging across the face at the turn of a wave: the depth shows it in two loose
    pieces (joined to the body nowhere without a depth jump) as far out as each other, on the far side
    of the spine. The hand keeps its id on one; the other is not the other arm's hand. UTD-MHAD subject
    4's waves, seen 0.7 m farther away or at 0.85x size, gave a phantom left hand there for a few frames:
    too close to the waving hand for its swing to count, and it swiped right itself. Joined to the body
    there, the same find is the other arm's hand."""
    def second_piece(loose: bool) -> tuple:
        tracker = HandTracker()
        torso, shoulder = np.array([0.0, 0.0, 2100.0]), np.array([150.0, 300.0, 2000.0])
        found = np.array([-150.0, 300.0, 2000.0])
        first = tracker._update_tracks(0.0, [Candidate(found, 420.0, False, shoulder, 1.0)], torso, True)
        hand = found + np.array([-30.0, 0.0, 0.0])
        forearm = found + np.array([110.0, -10.0, 0.0])
        pieces = [Candidate(hand, 425.0, False, hand, 1.0, loose=True),
                  Candidate(forearm, 425.0, False, forearm if loose else np.array([-150.0, 300.0, 2000.0]), 1.0,
                            loose=loose)]
        return first, tracker._update_tracks(1 / 30, pieces, torso, True)
    first, after = second_piece(loose=True)
    assert [h.id for h in after] == [first[0].id]
    _, after = second_piece(loose=False)
    assert sorted(h.side for h in after) == sorted([Side.RIGHT, Side.LEFT])


def test_a_second_find_on_the_side_of_a_hand_in_view_is_a_hand_only_once_seen_again():
    """A whole arm across the face can show two ends on the side where it joins the body: the hand and,
    a forearm or more away, its elbow, farther from the neck. UTD-MHAD subject 4's wave, with the
    sensor's noise doubled, gave a second right hand there for one frame, 280 mm from the waving one:
    too near for the swings to count. Such a find, however much of a palm it shows, becomes a hand once
    seen again; a hand that stays is reported from its second frame."""
    def frames(elbow_frames: int) -> list[tuple]:
        tracker = HandTracker()
        torso, root = np.array([-90.0, -120.0, 2860.0]), np.array([70.0, 160.0, 2600.0])
        hand, elbow = np.array([-220.0, 230.0, 2570.0]), np.array([30.0, 180.0, 2590.0])
        out = [tracker._update_tracks(0.0, [Candidate(hand, 330.0, False, root, 0.8)], torso, True)]
        for i in range(1, 4):
            found = [Candidate(hand + (0.0, 5.0 * i, 0.0), 330.0, False, hand, 0.6)]
            if i <= elbow_frames:
                found.append(Candidate(elbow, 350.0, False, elbow, 0.97))
            out.append(tracker._update_tracks(i / 30, found, torso, True))
        return [tuple(h.id for h in hands if h.state is not HandState.LOST) for hands in out]
    once = frames(elbow_frames=1)
    assert all(ids == once[0] for ids in once)
    stays = frames(elbow_frames=3)
    assert stays[1] == stays[0] and len(stays[2]) == 2 and stays[3] == stays[2]


def test_a_hand_out_of_sight_is_not_found_again_while_another_hand_of_its_side_is_in_view():
    """An arm has one hand. A hanging right hand seen for a frame, then the arm rising into a wave, gives
    two right tracks; the first, out of sight, was found again half a second later on a piece of the
    waving arm (UTD-MHAD subject 4's wave played 0.7x faster), which ended the wave. While another hand of
    its side is in view, that is the side's hand; alone, the hand out of sight is found again."""
    def found_again(other_in_view: bool) -> bool:
        tracker = HandTracker()
        torso, root = np.array([0.0, 0.0, 2600.0]), np.array([100.0, 150.0, 2500.0])
        low, up = np.array([270.0, -320.0, 2600.0]), np.array([250.0, 300.0, 2400.0])
        first = tracker._update_tracks(0.0, [Candidate(low, 300.0, False, root, 0.8)], torso, True)
        waving = [Candidate(up + (-20.0 * i, 0.0, 0.0), 500.0, False, root, 0.8) for i in range(16)]
        for i in range(1, 15):
            tracker._update_tracks(i / 30, waving[i:i + 1] if other_in_view else [], torso, True)
        piece = np.array([50.0, 150.0, 2550.0])  # within the first track's gate
        after = tracker._update_tracks(15 / 30, [Candidate(piece, 350.0, False, piece, 0.9)]
                                       + (waving[15:] if other_in_view else []), torso, True)
        return first[0].id in {h.id for h in after if h.state is not HandState.LOST}
    assert not found_again(other_in_view=True)
    assert found_again(other_in_view=False)
