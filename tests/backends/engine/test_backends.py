"""The named engine backends on real rendered depth, and `issv track` as a real process."""
from __future__ import annotations

import io
import json
import re
from dataclasses import replace
import subprocess
import sys

import numpy as np
import pydantic
import pytest

from backends.engine.backend import (OpenISSBackend, OpenISSNiteBackend, OpenISSNuitrackBackend,
                                     SimpleOpenNIBackend)
from backends.engine.recognizer import NITE_DICTIONARY, NUITRACK_DICTIONARY, GestureRecognizer
from backends.engine.tracker import HandTracker, TrackerOptions
from backends.engine.trunk import BodyOptions
from host import DepthFrame, GestureState, GestureType, HandState, Intrinsics, Side, Source
from host.commands.track import track
from host.errors import UserError
from host.loop import MAX_FAILED_IN_A_ROW
from host.plugins import default_registry
from tests.backends.engine.performer import WAVE_THEN_REST, frames, idle, swipe_cut_short, write_clip
from sources.clip import ClipSource
from tests.conftest import real_data

NITE_TYPES = set(NITE_DICTIONARY.values())
NUITRACK_TYPES = set(NUITRACK_DICTIONARY.values())


class ListSource(Source):
    """A source over frames already rendered (the synthetic performer's), so each test renders once."""

    name = "frames"

    def __init__(self, depth_frames) -> None:
        super().__init__()
        self.frames = depth_frames
        self.intrinsics = depth_frames[0].intrinsics

    def open(self) -> None:
        self._i = 0

    def read(self):
        if self._i >= len(self.frames):
            return None
        self._i += 1
        return self.frames[self._i - 1]


@pytest.fixture(scope="module")
def wave():
    return frames(WAVE_THEN_REST)


def play(backend_cls, depth_frames, options=None, hands=True, gestures=True):
    backend = backend_cls(ListSource(depth_frames), options)
    backend.init()
    if hands:
        backend.start_hand_tracking()
    if gestures:
        backend.start_gesture_detection()
    out = []
    while (frame := backend.update()) is not None:
        out.append(frame)
    backend.stop()
    return out


def completed(frames_):
    return [g for f in frames_ for g in f.gestures if g.state is GestureState.COMPLETE]


def test_all_four_are_registered_and_available():
    """The NiTE and Nuitrack modes are registered through their SDK adapters (backends/sdk)."""
    registry = default_registry()
    for cls in (OpenISSBackend, SimpleOpenNIBackend, OpenISSNiteBackend, OpenISSNuitrackBackend):
        entry = registry.get("backends", cls.name)
        assert entry is not None and issubclass(entry.cls, cls) and entry.availability() is None


def test_openiss_reports_hands_and_the_wave_with_its_hand(wave):
    out = play(OpenISSBackend, wave)
    assert [f.seq for f in out] == list(range(1, len(wave) + 1))
    assert all(f.backend == "openiss" and f.depth is wave[i] for i, f in enumerate(out))
    assert all(f.capture_time == f.depth.capture_time for f in out)
    waves = [g for g in completed(out) if g.name == "wave"]
    assert waves, "the synthetic wave was not recognised"
    hand_ids = {h.id for f in out for h in f.hands}
    assert waves[0].hand_id in hand_ids and waves[0].side.value == "right"
    assert 0 < waves[0].confidence <= 1


def test_a_child_is_tracked_with_a_childs_body_and_every_gesture_of_theirs_recognised():
    """A 1.2 m child 2 m from the camera, the floor in view: their height scales the tracker's adult
    anatomy (backends/engine/anatomy.py). With an adult's, the child's torso was placed 185 mm low,
    the neck and shoulders 150 mm, the left elbow and the hand hanging at rest were never found, and a
    wave was all that was recognised, one the child never made."""
    steps = [{"action": a} for a in ("swipe_right", "click", "swipe_left", "hand_raise")]
    child = frames([idle(0.6), *steps, idle(0.8)], height_mm=1200, distance_mm=2000, width=320, height=240)
    out = play(OpenISSBackend, child)
    assert [g.name for g in completed(out)] == [a["action"] for a in steps]
    for joint in ("torso", "neck", "left_shoulder", "right_shoulder", "left_elbow", "right_elbow", "left_hand",
                  "right_hand"):
        found = [(f.users[0].joints[joint], f.depth.truth.body[joint])
                 for f in out if f.users and joint in f.users[0].joints]
        errors = [np.linalg.norm(np.subtract(j.position, truth)) for j, truth in found if j.confidence > 0]
        assert errors and np.median(errors) < 120, joint


def test_stopped_tracking_and_detection_report_nothing(wave):
    out = play(OpenISSBackend, wave, hands=False, gestures=False)
    assert len(out) == len(wave)
    assert not any(f.hands or f.gestures for f in out)


def test_nite_mode_hands_only_after_a_focus_gesture_from_that_hand(wave):
    out = play(OpenISSNiteBackend, wave)
    focus = next(i for i, f in enumerate(out) for g in f.gestures
                 if g.state is GestureState.COMPLETE and g.name in ("wave", "click"))
    assert not any(f.hands for f in out[:focus]), "hands before the focus gesture"
    first = out[focus].hands
    assert first and first[0].state is HandState.NEW
    gesture = next(g for g in out[focus].gestures if g.state is GestureState.COMPLETE)
    assert first[0].id == gesture.hand_id
    assert {g.type for f in out for g in f.gestures} <= NITE_TYPES
    openiss = play(OpenISSBackend, wave)
    assert any(f.hands for f in openiss[:focus]), "the open engine reports hands before any gesture"


def test_simpleopenni_presents_kinect_v1_geometry_whatever_the_source():
    small = frames(WAVE_THEN_REST, width=320, height=240)
    out = play(SimpleOpenNIBackend, small)
    assert all((f.depth.width, f.depth.height) == (640, 480) for f in out)
    assert out[0].depth.intrinsics == Intrinsics.from_fov(640, 480, 57, 43)
    assert {g.type for f in out for g in f.gestures} <= NITE_TYPES
    assert any(g.type is GestureType.WAVE for g in completed(out))


def test_nuitrack_mode_names_and_sides(wave):
    out = play(OpenISSNuitrackBackend, wave)
    assert {g.type for f in out for g in f.gestures} <= NUITRACK_TYPES
    assert any(g.type is GestureType.WAVING for g in completed(out))
    first_gesture = next(i for i, f in enumerate(out) if f.gestures)
    assert any(f.hands for f in out[:first_gesture]), "no focus gesture needed before hands"
    assert all(h.side.value in ("left", "right") for f in out for h in f.hands)


def test_nuitrack_mode_reports_both_hands_while_the_user_is_in_view(wave):
    """Nuitrack's hands: ids 1 (left) and 2 (right), resting ones measured where they hang, LOST once
    after the user left."""
    step = wave[1].timestamp - wave[0].timestamp
    empty = [DepthFrame(np.zeros_like(wave[-1].data), wave[-1].intrinsics, frame_id=len(wave) + i,
                        timestamp=wave[-1].timestamp + (i + 1) * step, mirrored=wave[-1].mirrored)
             for i in range(int(2.0 / step))]  # the performer walks out: two seconds of empty depth
    out = play(OpenISSNuitrackBackend, wave + empty)
    in_view, gone = out[:len(wave)], out[len(wave):]
    assert all({(h.id, h.side.value, h.user_id) for h in f.hands} == {(1, "left", 1), (2, "right", 1)}
               for f in in_view)
    assert {h.state for h in in_view[0].hands} == {HandState.NEW}
    assert all(h.state is not HandState.NEW for f in in_view[1:] for h in f.hands)
    resting = [(h, d.truth.hands[h.side]) for f, d in zip(in_view, wave) for h in f.hands if h.extended is False]
    seen = [(h, d.truth.hands[h.side]) for f, d in zip(in_view, wave) for h in f.hands if h.extended]
    assert resting and seen, "both resting and extended hands"
    # The synthetic truth is the palm centre, about 100 mm above the fingertips, where the depth
    # ends the hanging arm; the Kinect skeleton of the real clips (tests below) puts its hand lower.
    error = np.array([np.subtract(h.position, truth) for h, truth in resting])
    assert np.median(np.hypot(error[:, 0], error[:, 2])) < 50, "a resting hand is measured beside the hip"
    assert np.median(np.abs(error[:, 1])) < 150, "at the lower end of the hanging arm"
    assert {h.side.value for h, _ in seen} == {"right"}, "only the waving hand is extended"
    waves = [g for g in completed(out) if g.name == "wave"]
    assert waves and all(g.hand_id == 2 for g in waves), "gestures name the side's id"
    # out of sight, the user is still tracked (hands held where last seen) until the user is LOST
    timeout = OpenISSNuitrackBackend.Options().people.lost_timeout_s
    held = [(f, h) for f, d in zip(gone, empty) for h in f.hands if h.in_view]
    assert all(h.state is HandState.TRACKING for _, h in held)
    assert {f.seq for f, _ in held} == {f.seq for f, d in zip(gone, empty) if d.timestamp - wave[-1].timestamp <= timeout}
    lost = [h for f in gone for h in f.hands if not h.in_view]
    assert sorted((h.id, h.state) for h in lost) == [(1, HandState.LOST), (2, HandState.LOST)]


CARRY = [{"action": "idle", "duration": 1.0}, {"action": "walk", "x_mm": 795.0}, {"action": "click", "hand": "right"},
         {"action": "walk", "x_mm": -805.0}, {"action": "click", "hand": "right"}, {"action": "idle", "duration": 0.5}]


@pytest.mark.parametrize("other_arm_mm, rule_on", [(100.0, True), (1e9, False)])
def test_a_hand_out_of_sight_is_not_found_again_on_the_other_arm(other_arm_mm, rule_on):
    """DigiEVISS' carry: walking sideways with the arms low, then a click with the right hand. The
    left hand, last seen swinging, must not be found again in the right hand rising for the click:
    the click is the right hand's, and nothing swipes. With the rule off (1e9 mm) the left hand's
    track takes the right hand and the click with it."""
    walk = frames(CARRY, seed=7)
    out = play(OpenISSBackend, walk, OpenISSBackend.Options(other_arm_mm=other_arm_mm))
    clicks = [g for g in completed(out) if g.name == "click"]
    assert clicks
    assert all(g.side is Side.RIGHT for g in clicks) is rule_on, [(g.hand_id, g.side) for g in clicks]
    if rule_on:
        assert not any(g.name.startswith("swipe") for g in completed(out))


def head_as_hand(depth_frames, options: TrackerOptions) -> int:
    """Frames' worth of reported hands at the head (within 200 mm) and near no hand (250 mm)."""
    tracker, count = HandTracker(options), 0
    for f in depth_frames:
        for h in tracker.process(f).hands:
            near_head = np.linalg.norm(np.subtract(h.position, f.truth.body["head"])) < 200
            near_hand = min(np.linalg.norm(np.subtract(h.position, p)) for p in f.truth.hands.values()) < 250
            count += h.state is not HandState.LOST and near_head and not near_hand
    return count


def test_walking_sideways_keeps_the_shoulders_and_the_head_is_no_hand():
    """Side-on, the chest is 220-280 mm deep: an opening as wide as that lost the shoulders, the
    shoulder line dropped and the head became a hand. The default 180 mm outline keeps them."""
    walk = frames(CARRY, seed=7)
    assert head_as_hand(walk, TrackerOptions()) <= 0.05 * len(walk)
    old = TrackerOptions(body=BodyOptions(outline_width_mm=220))
    assert head_as_hand(walk, old) > 0.1 * len(walk), "the scenario no longer shows the side-on head phantom"


def test_recognizer_classmethod_uses_the_mode_and_the_gesture_overrides():
    assert OpenISSNiteBackend.recognizer().dictionary == NITE_DICTIONARY
    assert OpenISSNuitrackBackend.recognizer().dictionary == NUITRACK_DICTIONARY
    options = OpenISSBackend.Options(gestures={"swipe_min_travel_mm": 300})
    assert OpenISSBackend.recognizer(options).rules.swipe_min_travel_mm == 300


def test_options_are_checked():
    with pytest.raises(pydantic.ValidationError):
        OpenISSBackend.Options(smoothness=3)
    with pytest.raises(pydantic.ValidationError):
        OpenISSBackend.Options(gestures={"swipe_travel": 300})
    options = OpenISSBackend.Options(lost_timeout_s=1.0, smoothing={"beta": 0.0})
    assert options.lost_timeout_s == 1.0 and options.smoothing.beta == 0.0


# -- issv track -----------------------------------------------------------------------------------

def issv(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "host", *args], capture_output=True, text=True, timeout=300)


@pytest.fixture(scope="module")
def clips(tmp_path_factory, wave):
    folder = tmp_path_factory.mktemp("clips")
    return write_clip(folder / "wave.npz", wave), write_clip(folder / "start.npz", wave[:20])


def test_the_recogniser_gets_only_the_hands_found_in_each_frame(wave, monkeypatch):
    engine = OpenISSBackend().build_engine()
    given = []
    update = GestureRecognizer.update
    monkeypatch.setattr(GestureRecognizer, "update",
                        lambda self, t, hands, *rest: given.append([h.id for h in hands]) or update(self, t, hands, *rest))
    frames_with_a_dropout = wave[:40] + [replace(wave[40], data=np.zeros_like(wave[40].data))] + wave[41:45]
    results = [engine.step(f) for f in frames_with_a_dropout]
    assert results[40].hands and not results[40].seen  # held: reported to effects
    assert given[40] == [] and given[39] == [h.id for h in results[39].hands]


def test_track_prints_a_hands_line_per_frame_and_the_gesture_events(clips, wave):
    result = issv("track", str(clips[0]))
    assert result.returncode == 0, result.stderr
    lines = [json.loads(line) for line in result.stdout.splitlines()]
    hands = [e for e in lines if e["type"] == "hands"]
    assert len(hands) == len(wave)
    assert all("clip" not in e for e in lines)
    gestures = [e for e in lines if e["type"] == "gesture"]
    assert any(e["name"] == "wave" and e["native"] == "WAVE" and e["state"] == "complete" for e in gestures)
    for e in gestures:
        assert {"t", "name", "native", "state", "hand", "side", "position", "confidence"} <= set(e)
    tracked = [h for e in hands for h in e["hands"]]
    assert tracked and all(len(h["position"]) == 3 and h["side"] in ("left", "right") for h in tracked)


def test_track_completes_a_swipe_the_clip_ends_on(tmp_path):
    """The event line of a swipe only the clip's end completes comes after the last hands line;
    one hands line per frame all the same."""
    clip = swipe_cut_short(tmp_path / "cut.npz")
    result = issv("track", str(clip))
    assert result.returncode == 0, result.stderr
    lines = [json.loads(line) for line in result.stdout.splitlines()]
    assert sum(e["type"] == "hands" for e in lines) == len(np.load(clip)["depth"])
    done = [i for i, e in enumerate(lines) if e["type"] == "gesture" and e["state"] == "complete"]
    assert [lines[i]["name"] for i in done] == ["swipe_left"]
    assert done[0] == len(lines) - 1


def test_track_several_clips_tags_every_line(clips):
    result = issv("track", "--backend", "openiss-nuitrack", *map(str, clips))
    assert result.returncode == 0, result.stderr
    lines = [json.loads(line) for line in result.stdout.splitlines()]
    by_clip = {str(c): [e for e in lines if e.get("clip") == str(c)] for c in clips}
    assert all("clip" in e for e in lines)
    assert len([e for e in by_clip[str(clips[1])] if e["type"] == "hands"]) == 20
    assert all(e["native"] in {t.value for t in NUITRACK_TYPES} for e in lines if e["type"] == "gesture")


def test_track_bad_input_is_one_clear_line(tmp_path, clips):
    missing = issv("track", str(tmp_path / "nope.npz"))
    assert missing.returncode == 1 and "nope.npz" in missing.stderr and "Traceback" not in missing.stderr
    unknown = issv("track", "--backend", "kinect-magic", str(clips[0]))
    assert unknown.returncode == 1 and "kinect-magic" in unknown.stderr and "openiss" in unknown.stderr


class RaisingOnTheThirdFrame(OpenISSBackend):
    """Fails on the third frame (`repeat`: and on every frame after it)."""

    repeat = False

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.calls = 0

    def update(self):
        frame, self.calls = super().update(), self.calls + 1
        if self.calls == 3 or (self.repeat and self.calls > 3 and frame is not None):
            raise ZeroDivisionError("odd frame")
        return frame


def test_track_skips_a_frame_the_backend_raises_on_as_a_show_does(clips, capsys):
    out = io.StringIO()
    track(clips[0], RaisingOnTheThirdFrame, ClipSource, None, out)
    assert out.getvalue().count('"type": "hands"') == len(np.load(clips[0])["depth"]) - 1
    err = capsys.readouterr().err
    assert re.search(r"'openiss' raised ZeroDivisionError on frame 3 of .*wave\.npz: odd frame; the frame is skipped",
                     err), err


def test_track_names_the_clip_and_the_frame_of_a_backend_failing_frame_after_frame(clips):
    class Broken(RaisingOnTheThirdFrame):
        repeat = True

    out = io.StringIO()
    last = 3 + MAX_FAILED_IN_A_ROW - 1
    with pytest.raises(UserError, match=rf"'openiss' raised ZeroDivisionError on frame {last} of .*wave\.npz: odd frame"):
        track(clips[0], Broken, ClipSource, None, out)
    assert out.getvalue().count('"type": "hands"') == 2


def test_track_a_real_kinect_clip():
    clip = real_data("utd-mhad-dev", "clips", "a3_s1_t1_wave.npz")
    result = issv("track", str(clip))
    assert result.returncode == 0, result.stderr
    lines = [json.loads(line) for line in result.stdout.splitlines()]
    assert sum(e["type"] == "hands" for e in lines) > 30
    assert any(e["type"] == "hands" and e["hands"] for e in lines), "no hand found in a real wave"
