"""`replay` plays a recording back exactly as it was tracked; seek and loop keep time consistent."""
from __future__ import annotations

import numpy as np
import pytest

from backends.replay import ReplayBackend, ReplayOptions
from host import Effect, GestureState, Stage
from host.loop import EffectSlot, Show
from tests.recordings import as_tracked, record, tracked_live


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    return record(tmp_path_factory.mktemp("replay"), seconds=4.0)


def replayed(path, limit=10_000, **options) -> list:
    frames = []
    with ReplayBackend(None, ReplayOptions(path=str(path), realtime=False, **options)) as backend:
        while len(frames) < limit and (frame := backend.update()) is not None:
            frames.append(frame)
    return frames


@pytest.mark.parametrize("backend", ["truth", "openiss"])
def test_replay_gives_the_same_hands_and_gestures_at_the_same_timestamps(recording, tmp_path, backend):
    if backend != "truth":  # the open engine, tracking the synthetic performer's depth
        recording = record(tmp_path, seconds=4.0, backend=backend, width=320, height=240)
    source = {} if backend == "truth" else {"width": 320, "height": 240}
    live = tracked_live(4.0, backend, **source)
    played = replayed(recording)
    assert as_tracked(played) == as_tracked(live)
    assert any(f.gestures for f in played) and sum(bool(f.hands) for f in played) > len(played) / 2
    assert {f.backend for f in played} == {backend}
    for a, b in zip(played[::40], live[::40]):
        assert np.array_equal(a.depth.data, b.depth.data) and a.depth.intrinsics == b.depth.intrinsics


def test_seek_starts_at_that_source_time(recording):
    everything = replayed(recording)
    later = replayed(recording, seek=2.0)
    assert later[0].timestamp == pytest.approx(2.0)
    assert as_tracked(later) == as_tracked([f for f in everything if f.timestamp >= later[0].timestamp])


def test_loop_plays_again_with_time_running_forwards(recording):
    once = replayed(recording)
    twice = replayed(recording, limit=2 * len(once), loop=True)
    times = [f.timestamp for f in twice]
    assert len(twice) == 2 * len(once) and all(b > a for a, b in zip(times, times[1:]))
    again = twice[len(once):]
    shift = again[0].timestamp - once[0].timestamp
    assert shift == pytest.approx(once[-1].timestamp - once[0].timestamp + 1 / 30)
    assert [f.hands for f in again] == [f.hands for f in once]
    assert [g.timestamp - shift for f in again for g in f.gestures] == pytest.approx(
        [g.timestamp for f in once for g in f.gestures])


class Gestures(Effect):
    name = "gestures-seen"

    def __init__(self):
        super().__init__()
        self.seen = []

    def on_gesture(self, gesture):
        self.seen.append(gesture)


def test_a_replayed_show_delivers_every_recorded_gesture_once(recording):
    effect = Gestures()
    backend = ReplayBackend(None, ReplayOptions(path=str(recording), realtime=False))
    Show(backend, [EffectSlot(effect, "effects[0]")], Stage((64, 48), 240.0, "replay")).run()
    recorded = [g for f in tracked_live(4.0) for g in f.gestures]
    assert effect.seen == recorded and any(g.state is GestureState.COMPLETE for g in recorded)
