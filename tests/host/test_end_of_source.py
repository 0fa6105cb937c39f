"""A swipe that only the end of the source completes reaches the consumers of a show: a recording
(and its replay) and a comparison (the network: tests/backends/network/test_loopback.py)."""
from __future__ import annotations

import pytest

from backends.replay import ReplayBackend
from host import GestureState
from host.compare import run_backend
from host.recording import Recording
from tests.backends.engine.performer import swipe_cut_short
from tests.recordings import record_profile, write_profile


def completed(gestures) -> list[str]:
    return [g.name for g in gestures if g.state is GestureState.COMPLETE]


@pytest.fixture(scope="module")
def clip(tmp_path_factory):
    return swipe_cut_short(tmp_path_factory.mktemp("clip") / "cut.npz")


@pytest.fixture(scope="module")
def recording(clip, tmp_path_factory):
    folder = tmp_path_factory.mktemp("rec")
    prof = write_profile(folder / "p.toml", {"name": "clip", "path": str(clip)}, {"name": "openiss"})
    return record_profile(prof, folder / "cut.mcap")


def test_the_recording_keeps_it_after_the_last_frame_and_replay_gives_it_at_the_end(recording):
    rec = Recording(recording)
    during = [g for f in rec.frames() for g in f.gestures]
    assert "swipe_left" not in completed(during) and completed(rec.end_gestures) == ["swipe_left"]
    with ReplayBackend(None, ReplayBackend.Options(path=str(recording), realtime=False)) as replay:
        assert "swipe_left" not in completed(g for f in iter(replay.update, None) for g in f.gestures)
        assert completed(replay.finish()) == ["swipe_left"]


def test_a_comparison_counts_it(recording):
    assert completed(run_backend("openiss", recording).gestures) == ["swipe_left"]
