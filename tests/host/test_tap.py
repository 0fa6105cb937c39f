"""The sensor tap sees every frame a backend makes, and nothing else."""
from __future__ import annotations

from host import Frame
from host.tap import SensorTap
from tests.host.test_loop import QuietBackend


def test_the_tap_observes_frames_only_and_passes_nothing_yet_on():
    seen: list[Frame] = []
    tap = SensorTap(QuietBackend(2, first=1), seen.append)
    answers = [tap.update() for _ in range(4)]
    assert answers[0] is False and answers[3] is False  # before and after the two frames
    assert seen == answers[1:3] and [f.seq for f in seen] == [1, 2]
