"""Tests for `hand-glow`: run them with `python -m pytest` in this folder."""
from host import Frame, Gesture, GestureState, GestureType, Hand, HandState, Side, Stage

from issv_hand_glow import HandGlow


def make_effect(**options):
    effect = HandGlow(HandGlow.Options(**options))
    effect.setup(Stage(size=(640, 480), fps=30.0, backend="test"))
    return effect


def gesture(kind, state=GestureState.COMPLETE):
    return Gesture(kind, state, (100.0, 200.0, 1500.0), hand_id=1, side=Side.RIGHT)


def test_counts_the_completed_gestures_it_listens_for(capsys):
    effect = make_effect(gestures=["wave"])
    effect.on_gesture(gesture(GestureType.WAVE, GestureState.IN_PROGRESS))
    effect.on_gesture(gesture(GestureType.WAVING))  # Nuitrack's wave is a wave too
    effect.on_gesture(gesture(GestureType.CLICK))
    assert effect.count == 1
    assert "hand-glow: wave by the right hand" in capsys.readouterr().out


def test_follows_the_hands():
    effect = make_effect()
    effect.on_frame(Frame(1, 0.0, None, (Hand(7, HandState.TRACKING, (10.0, 20.0, 1500.0)),)))
    assert effect.hands == {7: (10.0, 20.0, 1500.0)}
