"""bench.gestures' worst person: the performer and gesture a variation loses most."""
from __future__ import annotations

from bench.gestures import worst_person


def test_the_worst_person_is_the_performer_and_gesture_with_the_lowest_recall():
    labels = {"a18_s1_t1_push.npz": "push", "a18_s3_t1_push.npz": "push", "a18_s3_t2_push.npz": "push",
              "a3_s4_t1_wave.npz": "wave", "a3_s4_t2_wave.npz": "wave", "a22_s2_t1_jog.npz": "jog"}
    completed = {"a18_s1_t1_push.npz": {"click"}, "a18_s3_t1_push.npz": set(), "a18_s3_t2_push.npz": {"click"},
                 "a3_s4_t1_wave.npz": {"wave"}, "a3_s4_t2_wave.npz": {"wave", "swipe_left"},
                 "a22_s2_t1_jog.npz": {"wave"}}  # a negative's false fire is no one's recall
    assert worst_person(completed, labels) == {"person": "s3", "gesture": "click", "recall": 0.5}
    assert worst_person({"a22_s2_t1_jog.npz": set()}, {"a22_s2_t1_jog.npz": "jog"}) is None
