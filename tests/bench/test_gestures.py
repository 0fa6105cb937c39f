"""bench.gestures' worst person (the performer and gesture a variation loses most) and its depth variations."""
from __future__ import annotations

import numpy as np
import pytest

from bench.gestures import DEPTH_VARIATIONS, worst_person
from sources.clip import Clip


def test_the_worst_person_is_the_performer_and_gesture_with_the_lowest_recall():
    labels = {"a18_s1_t1_push.npz": "push", "a18_s3_t1_push.npz": "push", "a18_s3_t2_push.npz": "push",
              "a3_s4_t1_wave.npz": "wave", "a3_s4_t2_wave.npz": "wave", "a22_s2_t1_jog.npz": "jog"}
    completed = {"a18_s1_t1_push.npz": {"click"}, "a18_s3_t1_push.npz": set(), "a18_s3_t2_push.npz": {"click"},
                 "a3_s4_t1_wave.npz": {"wave"}, "a3_s4_t2_wave.npz": {"wave", "swipe_left"},
                 "a22_s2_t1_jog.npz": {"wave"}}  # a negative's false fire is no one's recall
    assert worst_person(completed, labels) == {"person": "s3", "gesture": "click", "recall": 0.5}
    assert worst_person({"a22_s2_t1_jog.npz": set()}, {"a22_s2_t1_jog.npz": "jog"}) is None


@pytest.mark.parametrize("name, frames, seconds",
                         [("faster (0.7x time)", 21, 0.7), ("slower (1.4x time, 21 fps)", 30, 1.4)])
def test_a_faster_performer_skips_frames_and_a_slower_one_spreads_them(tmp_path, name, frames, seconds):
    """One second at 30 Hz, each frame's depth its own index: the faster performance is the same frames, in
    order, some skipped, over 0.7 s; the slower one every frame over 1.4 s."""
    depth = np.zeros((30, 4, 4), np.uint16)
    depth[:, 2, 2] = 1000 + np.arange(30)
    np.savez(tmp_path / "c.npz", depth=depth, timestamps=np.arange(30) / 30, intrinsics=np.array([4.0, 4.0, 2.0, 2.0]))
    varied = DEPTH_VARIATIONS[name].apply(Clip(tmp_path / "c.npz"), np.random.default_rng(0))
    shown = varied["depth"][:, 2, 2].astype(int) - 1000
    assert len(shown) == frames and shown[0] == 0 and shown[-1] >= 28 and np.all(np.diff(shown) >= 1)
    assert varied["timestamps"][-1] == pytest.approx(29 / 30 * seconds, abs=0.02)
