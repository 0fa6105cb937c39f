"""SimpleOpenNI-style callbacks from the host's frames and gestures, and the ported Hands sketch."""
from pathlib import Path

import cv2
import numpy as np
import pytest

from host import (DepthFrame, Frame, Gesture, GestureState, GestureType, Hand, HandState, Intrinsics,
                  SimpleOpenNIEffect, Stage)
from host.assemble import make_backend
from host.loop import EffectSlot, Show
from host.profile import Output, parse

K = Intrinsics(100, 100, 8, 6)
EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "issv2-hands"


class Log(SimpleOpenNIEffect):
    name = "log"

    def setup(self, stage):
        super().setup(stage)
        self.calls = []

    def on_new_hand(self, hand_id, pos): self.calls.append(("new", hand_id, pos))
    def on_tracked_hand(self, hand_id, pos): self.calls.append(("tracked", hand_id, pos))
    def on_lost_hand(self, hand_id): self.calls.append(("lost", hand_id))
    def on_completed_gesture(self, gesture_type, pos): self.calls.append(("completed", gesture_type, pos))
    def on_create_hands(self, hand_id, pos, time): self.calls.append(("create", hand_id, time))
    def on_update_hands(self, hand_id, pos, time): self.calls.append(("update", hand_id, time))
    def on_destroy_hands(self, hand_id, time): self.calls.append(("destroy", hand_id, time))
    def on_recognize_gesture(self, name, id_position, end_position):
        self.calls.append(("recognize", name, id_position, end_position))


def frame(seq, *hands):
    depth = DepthFrame(np.zeros((12, 16), np.uint16), K, seq, seq / 10)
    return Frame(seq, 0.0, depth, tuple(Hand(i, state, p) for i, state, p in hands))


def test_hands_appear_are_tracked_and_are_lost():
    effect = Log()
    effect.setup(Stage((64, 48), 30.0, "test"))
    a, b = (1.0, 2.0, 1500.0), (3.0, 4.0, 1600.0)
    effect.on_frame(frame(1, (1, HandState.NEW, a)))
    effect.on_frame(frame(2, (1, HandState.TRACKING, b), (2, HandState.NEW, a)))
    effect.on_frame(frame(3, (1, HandState.LOST, b), (2, HandState.TRACKING, a)))  # LOST counts as gone
    effect.on_frame(frame(4))
    assert effect.calls == [
        ("new", 1, a), ("create", 1, 0.1),
        ("tracked", 1, b), ("update", 1, 0.2), ("new", 2, a), ("create", 2, 0.2),
        ("tracked", 2, a), ("update", 2, 0.3), ("lost", 1), ("destroy", 1, 0.3),
        ("lost", 2), ("destroy", 2, 0.4),
    ]


def test_completed_gestures_with_a_backend_independent_type_and_where_they_began():
    effect = Log()
    effect.setup(Stage((64, 48), 30.0, "test"))
    start, end = (0.0, 0.0, 1500.0), (0.0, 0.0, 1200.0)
    effect.on_gesture(Gesture(GestureType.PUSH, GestureState.IN_PROGRESS, start, hand_id=3))
    effect.on_gesture(Gesture(GestureType.WAVING, GestureState.COMPLETE, end, hand_id=4))
    effect.on_gesture(Gesture(GestureType.PUSH, GestureState.COMPLETE, end, hand_id=3))
    assert effect.calls == [
        ("completed", GestureType.WAVE, end), ("recognize", "wave", end, end),
        ("completed", GestureType.CLICK, end), ("recognize", "click", start, end),
    ]
    assert effect.calls[2][1] == Log.GESTURE_CLICK  # Nuitrack's PUSH reads as SimpleOpenNI's click


@pytest.fixture
def hands_sketch(monkeypatch):
    monkeypatch.syspath_prepend(str(EXAMPLE))
    import issv2_hands
    return issv2_hands.Hands


def sketch_show(tmp_path, effect_cls, renderer=None, stage=None):
    profile = parse('backend = "truth"\n[source]\nname = "synthetic"\nseed = 2\nchoreography = ['
                    '{action = "idle", duration = 0.5}, {action = "click", hand = "right"}, '
                    '{action = "idle", duration = 0.5}]\n', str(tmp_path / "p.toml"), tmp_path)
    effect = effect_cls()
    stage = stage or Stage((160, 120), 1000.0, "truth")
    show = Show(make_backend(profile, realtime=False), [EffectSlot(effect, "effects[0]")], stage, renderer=renderer)
    show.run()
    return effect


def test_the_ported_hands_sketch_runs_without_a_renderer(hands_sketch, tmp_path, capsys):
    effect = sketch_show(tmp_path, hands_sketch)
    out = capsys.readouterr().out
    assert out.count("onNewHand - handId:") == 2  # both of the performer's hands
    assert "onCompletedGesture - gestureType: CLICK" in out
    assert sorted(effect.hand_path_list) == [1, 2]
    assert all(1 < len(path) < 20 for path in effect.hand_path_list.values())


def test_the_ported_hands_sketch_draws_its_paths(hands_sketch, tmp_path):
    from host.render import make_renderer
    snapshot = tmp_path / "hands.png"
    output = Output(size=(160, 120), mode="headless", hud=False, snapshot=str(snapshot))
    stage = Stage((160, 120), 1000.0, "truth")
    sketch_show(tmp_path, hands_sketch, make_renderer(output, stage), stage)
    image = cv2.imread(str(snapshot))
    b, g, r = (image[:, :, i].astype(int) for i in range(3))
    red, green = (r > 200) & (g < 80), (g > 200) & (r < 80)  # hand 1 red, hand 2 green (USER_CLR)
    assert red.sum() > 5 and green.sum() > 5
