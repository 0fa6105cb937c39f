"""The tracking bench times every backend on every frame, in turns, each on its own copy of the frames."""
from __future__ import annotations

from backends.engine.backend import OpenISSBackend, SimpleOpenNIBackend
from bench.tracking import TURN_FRAMES, WARMUP_FRAMES, synthetic_frames, time_backends


def spying(cls: type) -> type:
    """The backend, its engine noting each frame it tracks (time stamp, the depth array)."""
    class Spy(cls):
        tracked: list = []

        def build_engine(self):
            engine = super().build_engine()
            track = engine.track

            def noted(frame):
                Spy.tracked.append((frame.timestamp, frame.data))
                return track(frame)
            engine.track = noted
            return engine
    return Spy


def test_each_backend_tracks_every_frame_in_order_on_its_own_copy():
    frames = synthetic_frames((320, 240), seconds=0.6)  # 18 frames: turns of five, the last one short
    assert len(frames) % TURN_FRAMES
    spies = [spying(OpenISSBackend), spying(SimpleOpenNIBackend)]
    times = time_backends(spies, frames)
    for spy in spies:
        assert [t for t, _ in spy.tracked] == [f.timestamp for f in frames]
        assert len(times[spy][0]) == len(times[spy][1]) == len(frames) - WARMUP_FRAMES
        assert all(ms > 0 for ms in times[spy][0])
    first, second = ([data for _, data in spy.tracked] for spy in spies)
    assert all((a == f.data).all() and a is not f.data and b is not f.data and a is not b
               for a, b, f in zip(first, second, frames))
