"""The frame loop's promises: gestures exactly once and in order, newest frame wins,
one failing effect is disabled and the others lose nothing, stop() is always called, and a
time limit holds in wall time even when no frame ever comes."""
import signal
import subprocess
import sys
import time

import numpy as np

from host import Backend, DepthFrame, Effect, Frame, Gesture, GestureState, GestureType, Intrinsics, Stage
from host.errors import UserError
from host.loop import MAX_FAILED_IN_A_ROW, EffectSlot, Limits, Show

K = Intrinsics(100, 100, 8, 6)


class BurstBackend(Backend):
    """Makes `n` frames as fast as it can, each carrying two gesture events."""

    name = "burst"
    needs_source = False

    def __init__(self, n: int, period: float = 0.0):
        super().__init__(None)
        self.n, self.period, self.i, self.stopped = n, period, 0, False

    def update(self):
        if self.i >= self.n:
            return None
        time.sleep(self.period)
        self.i += 1
        depth = DepthFrame(np.zeros((12, 16), np.uint16), K, self.i, self.i / 30)
        gestures = tuple(Gesture(GestureType.SWIPE_LEFT, GestureState.COMPLETE, (0, 0, 1), hand_id=k, timestamp=self.i)
                         for k in range(2))
        return Frame(self.i, depth.capture_time, depth, (), gestures, self.name)

    def stop(self):
        self.stopped = True


class Recorder(Effect):
    name = "recorder"

    def __init__(self, frame_delay=0.0, fail_on_frame=None):
        super().__init__()
        self.frame_delay, self.fail_on_frame = frame_delay, fail_on_frame
        self.events, self.frames = [], []

    def on_gesture(self, g):
        self.events.append((g.timestamp, g.hand_id))

    def on_frame(self, frame):
        if self.fail_on_frame is not None and frame.seq >= self.fail_on_frame:
            raise RuntimeError("boom")
        self.frames.append(frame.seq)
        time.sleep(self.frame_delay)


def run_show(backend, effects, fps=60.0, limits=Limits(), lossless=False):
    slots = [EffectSlot(e, f"effects[{i}]") for i, e in enumerate(effects)]
    show = Show(backend, slots, Stage((64, 48), fps, backend.name), limits=limits, lossless=lossless)
    return show, show.run()


def test_slow_show_loop_drops_frames_but_never_gestures():
    fast, slow = Recorder(), Recorder(frame_delay=0.02)
    backend = BurstBackend(200)
    show, metrics = run_show(backend, [slow, fast], fps=200)
    want = [(i, k) for i in range(1, 201) for k in range(2)]
    assert slow.events == want and fast.events == want
    assert metrics.frames == 200 and metrics.dropped > 0
    assert metrics.dropped + len(slow.frames) == 200
    assert slow.frames == sorted(slow.frames) and slow.frames[-1] == 200
    assert metrics.gestures_by_name == {"swipe_left": 400}
    assert backend.stopped


def test_a_lossless_show_gives_every_frame_to_a_slow_effect_in_step_with_its_gestures():
    """`issv run --fast`: an unpaced show waits for its effects, so a busy machine changes nothing."""
    slow = Recorder(frame_delay=0.005)
    seen = []
    slow.on_frame = lambda frame: (seen.append((frame.seq, [t for t, _ in slow.events])), time.sleep(0.005))
    show, metrics = run_show(BurstBackend(100), [slow], fps=200, lossless=True)
    assert [seq for seq, _ in seen] == list(range(1, 101)) and metrics.dropped == 0
    assert all(events[-1] == seq for seq, events in seen)  # a frame's gestures came just before it


def test_a_raising_effect_is_disabled_and_the_others_lose_nothing(capsys):
    broken, healthy = Recorder(fail_on_frame=3), Recorder()
    show, metrics = run_show(BurstBackend(30, period=0.005), [broken, healthy], fps=500)
    err = capsys.readouterr().err
    assert err.count("raised RuntimeError in on_frame: boom") == 1
    assert "effect 'recorder' (effects[0])" in err and "the show goes on" in err
    assert not show.effects[0].enabled and show.effects[1].enabled
    assert broken.frames == [1, 2] or broken.frames[-1] < 3
    assert len(healthy.events) == 60 and healthy.frames[-1] == 30


class FlakyBackend(BurstBackend):
    """Raises on the frames numbered in `bad` (odd depth images), and on every frame from
    `broken_from` on (a backend that is broken, not one frame)."""

    def __init__(self, n, bad=(), broken_from=float("inf")):
        super().__init__(n)
        self.bad, self.broken_from = set(bad), broken_from

    def update(self):
        frame = super().update()
        if frame is not None and (frame.seq in self.bad or frame.seq >= self.broken_from):
            raise ValueError(f"odd frame {frame.seq}")
        return frame


def test_a_backend_failing_on_a_few_frames_loses_only_those(capsys):
    recorder = Recorder()
    show, metrics = run_show(FlakyBackend(30, bad={5, 6, 20}), [recorder], fps=500)
    err = capsys.readouterr().err
    assert show.sensor_error is None and show.backend.stopped
    assert metrics.frames == 27 and metrics.failed == 3
    assert [i for i, _ in recorder.events[::2]] == [i for i in range(1, 31) if i not in {5, 6, 20}]
    assert err.count("backend 'burst' raised ValueError on frame 5: odd frame 5") == 1
    assert show.failed_frame == 20
    assert "the show goes on" in err and "odd frame 6" not in err


def test_a_backend_failing_frame_after_frame_ends_the_show():
    show, metrics = run_show(FlakyBackend(10_000, broken_from=10), [Recorder()], fps=500)
    assert isinstance(show.sensor_error, ValueError) and show.backend.stopped
    assert metrics.frames == 9 and metrics.failed == MAX_FAILED_IN_A_ROW


def test_frame_limit_stops_the_show_and_calls_stop():
    backend = BurstBackend(10_000)
    _, metrics = run_show(backend, [Recorder()], limits=Limits(frames=25))
    assert metrics.frames == 25 and backend.stopped


class QuietBackend(BurstBackend):
    """A live input (a network publisher): `first` answers of nothing yet (False), then `n` frames,
    then silence for ever (nobody says the stream ended). Notes whether stop() came mid-update()."""

    def __init__(self, n: int = 0, first: int = 0):
        super().__init__(n)
        self.first, self.calls, self.updating, self.stopped_mid_update = first, 0, False, False

    def update(self):
        self.updating, self.calls = True, self.calls + 1
        time.sleep(0.002)  # a transport's short poll
        frame = False if self.calls <= self.first else super().update()
        self.updating = False
        return False if frame is None else frame

    def stop(self):
        self.stopped_mid_update = self.updating
        super().stop()


def test_a_time_limit_ends_a_show_that_never_gets_a_frame_with_one_line_naming_its_input(monkeypatch):
    monkeypatch.setattr("host.loop.WALL_GRACE_S", 0.0)
    show, metrics = run_show(QuietBackend(), [Recorder()], limits=Limits(seconds=0.2))
    assert isinstance(show.sensor_error, UserError) and metrics.frames == 0
    assert str(show.sensor_error) == ("backend 'burst': no frame in 0.2 s (the time limit, 0.2 s, plus 0 s of grace); "
                                      "input: its own frames")
    assert show.backend.calls > 1 and show.backend.stopped and not show.backend.stopped_mid_update


def test_a_time_limit_holds_in_wall_time_once_frames_stop_coming(monkeypatch):
    monkeypatch.setattr("host.loop.WALL_GRACE_S", 0.0)
    show, metrics = run_show(QuietBackend(5), [Recorder()], limits=Limits(seconds=10.0))  # 5 frames: 0.13 s
    assert show.sensor_error is None and metrics.frames == 5 and show.backend.stopped


def test_frames_that_come_after_a_silence_are_all_shown():
    recorder = Recorder()
    show, metrics = run_show(QuietBackend(10, first=20), [recorder], limits=Limits(frames=10), lossless=True)
    assert show.sensor_error is None and recorder.frames == list(range(1, 11))


def test_a_stop_request_ends_a_show_waiting_for_its_first_frame_between_two_updates():
    backend = QuietBackend()
    show = Show(backend, [], Stage((64, 48), 60.0, backend.name),
                status=lambda s: s.request_stop() if backend.calls > 3 else None)
    show.run()
    assert show.sensor_error is None and backend.stopped and not backend.stopped_mid_update


SAYS_STARTED = """
import sys
from host import hookimpl
from host.cli import main
from host.plugins import default_manager

class SaysStarted:
    @hookimpl
    def host_started(self, show):
        print("started", file=sys.stderr, flush=True)

default_manager().register(SaysStarted(), name="says-started")
sys.exit(main(sys.argv[1:]))
"""


def test_sigterm_stops_a_running_show_cleanly(tmp_path, clip):
    profile = tmp_path / "p.toml"
    profile.write_text(f'backend = "truth"\n[source]\nname = "clip"\npath = "{clip}"\nloop = true\n'
                       '[[effects]]\nname = "console"\n[output]\nmode = "headless"\n')
    metrics = tmp_path / "m.json"
    proc = subprocess.Popen([sys.executable, "-c", SAYS_STARTED, "run", str(profile), "--metrics-json", str(metrics)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert proc.stderr.readline() == "started\n"  # the show runs (however long start-up took on this machine)
    time.sleep(0.5)
    proc.send_signal(signal.SIGTERM)
    out, err = proc.communicate(timeout=20)
    assert proc.returncode == 0, err
    assert "Traceback" not in err
    assert metrics.exists() and '"frames"' in metrics.read_text()


class SwipeAtTheEndBackend(BurstBackend):
    """Its source ends while a swipe is still being confirmed: `finish()` completes it."""

    def finish(self):
        return (Gesture(GestureType.SWIPE_RIGHT, GestureState.COMPLETE, (0, 0, 1), hand_id=9, timestamp=self.n),)


def test_gestures_completed_by_the_end_of_the_source_reach_the_effects():
    recorder = Recorder()
    _, metrics = run_show(SwipeAtTheEndBackend(5), [recorder])
    assert recorder.events[-1] == (5, 9) and len(recorder.events) == 11
    assert metrics.gestures_by_name == {"swipe_left": 10, "swipe_right": 1}
