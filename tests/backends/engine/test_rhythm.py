"""A wave told by its rhythm: swings too small for strokes (rhythm.py), on synthetic performances."""
from __future__ import annotations

import pytest

from backends.engine.recognizer import GestureRecognizer
from backends.engine.rules import GestureRules
from tests.backends.engine import choreography as c
from tests.backends.engine.test_recognizer import completed, perform

FINGER_WAVE = dict(amplitude=15.0, half_period=0.2, height=420.0)  # Kinder-Gator adults' finger waves


@pytest.mark.parametrize("noise_mm", [0.0, 2.0])
def test_a_raised_hand_waved_with_the_fingers_is_a_wave(noise_mm):
    """The hand joint swings 15 mm at 2.5 Hz beside the face, eight swings: below the strokes'
    hysteresis, so only its rhythm tells the wave."""
    assert completed(perform(c.wave(swings=8, **FINGER_WAVE), noise_mm=noise_mm)) == ["wave"]


def test_too_few_small_swings_or_small_swings_below_the_shoulders_are_no_wave():
    assert completed(perform(c.wave(swings=4, **FINGER_WAVE))) == []
    assert completed(perform(c.wave(swings=8, **(FINGER_WAVE | {"height": 100.0})))) == []  # at the chest


def test_small_swings_slower_than_a_wave_are_no_wave():
    """15 mm to and fro at 1 Hz: a raised hand swaying, not waving."""
    assert completed(perform(c.wave(swings=8, **(FINGER_WAVE | {"half_period": 0.5})))) == []


@pytest.mark.parametrize("seed", range(5))
def test_a_raised_hand_held_still_by_a_jittering_tracker_is_a_hand_raise_and_no_wave(seed):
    """Held up for three seconds, every coordinate jittering by 5 mm (standard deviation) each frame:
    reversals of a frame or two, along every axis alike, keep no wave's time."""
    recognizer = GestureRecognizer(GestureRules())
    performance = c.hand_raise(above_head=200, hold=3.0)
    events = []
    for t, hands, body in performance.frames(noise_mm=5.0, seed=seed):
        events += recognizer.update(t, hands, body, performance.mirrored)
    assert completed(events) == ["hand_raise"]


def test_the_rhythm_needed_is_overridable():
    rules = GestureRules(wave_rhythm_min_swings=10)
    assert completed(perform(c.wave(swings=8, **FINGER_WAVE), rules)) == []
