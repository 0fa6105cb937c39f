"""The frame loop: a sensor thread drives the backend, the show loop drives the effects.

Two paths, kept apart on purpose (docs/architecture.md, The frame loop):
- hands and depth travel in `Latest`, a one-frame slot: the newest frame wins, older ones are
  counted as dropped (the show loop may run slower or faster than the sensor);
- gesture events travel in `GestureQueue`, a FIFO that is never trimmed: every effect sees every
  event exactly once, in order, even when the show loop falls behind.
"""
from __future__ import annotations

import dataclasses
import sys
import threading
import time
from collections import deque
from dataclasses import dataclass
from typing import Any, Callable

import pluggy

from host.contracts import Backend, Effect, Source, Stage
from host.errors import UserError
from host.metrics import Metrics, input_of
from host.model import DepthFrame, Frame, Gesture
from host.plugins import Lifecycle


class PacedSource:
    """Wraps a source: paces a recorded one to real time and stamps every frame's capture time."""

    def __init__(self, source: Source, realtime: bool) -> None:
        self.inner = source
        self.realtime = realtime and not source.live
        self._origin: tuple[float, float] | None = None  # (wall time, source time) of frame 0

    def __getattr__(self, name: str) -> Any:
        return getattr(self.inner, name)

    def read(self) -> DepthFrame | None:
        frame = self.inner.read()
        if frame is None:
            return None
        if self.realtime:
            if self._origin is None:
                self._origin = (time.perf_counter(), frame.timestamp)
            due = self._origin[0] + (frame.timestamp - self._origin[1])
            delay = due - time.perf_counter()
            if delay > 0:
                time.sleep(delay)
        return dataclasses.replace(frame, capture_time=time.time())


def profile_source(source: Source | PacedSource | None) -> Source | None:
    """The source the profile named, under the pacer the host may have wrapped it in (a backend
    that hands the device to a middleware needs the source itself; exported as host.profile_source)."""
    return source.inner if isinstance(source, PacedSource) else source


class Latest:
    """The newest frame and how many frames were published (newest wins)."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._frame: Frame | None = None
        self._count = 0

    def publish(self, frame: Frame) -> None:
        with self._lock:
            self._frame, self._count = frame, self._count + 1

    def take(self) -> tuple[Frame | None, int]:
        with self._lock:
            return self._frame, self._count


class GestureQueue:
    """Gesture events in arrival order; drained whole by the show loop (deque is thread-safe)."""

    def __init__(self) -> None:
        self._events: deque[Gesture] = deque()

    def put_all(self, gestures: tuple[Gesture, ...]) -> None:
        self._events.extend(gestures)

    def drain(self) -> list[Gesture]:
        out = []
        while self._events:
            out.append(self._events.popleft())
        return out

    def __len__(self) -> int:
        return len(self._events)


@dataclass
class EffectSlot:
    """An effect in the stack, where the profile put it, and whether it is still running."""

    effect: Effect
    where: str
    blend: str = "normal"
    opacity: float = 1.0
    enabled: bool = True


@dataclass
class Limits:
    """When a show ends by itself: after N sensor frames or S seconds of source time, and with S
    after S + WALL_GRACE_S seconds of wall time at most (source time lags, or never starts when
    no frame comes: a network publisher that is not there)."""

    frames: int | None = None
    seconds: float | None = None


WALL_GRACE_S = 5.0  # source time may lag the wall clock: a paced source starting, a slow backend
MAX_FAILED_IN_A_ROW = 30  # a second of frames at 30 Hz: the backend is broken, not one frame


class Show:
    """Runs one show: owns timing, metrics and lifecycle; plugins only answer when called."""

    def __init__(self, backend: Backend, effects: list[EffectSlot], stage: Stage, *,
                 pm: pluggy.PluginManager | None = None, limits: Limits = Limits(),
                 renderer: Any = None, status: Callable[["Show"], None] | None = None,
                 label: str | None = None, hold: bool = False, lossless: bool = False) -> None:
        self.backend = backend
        self.effects = effects
        self.stage = stage
        self.pm = pm
        self.notify = Lifecycle(pm) if pm is not None else None  # the lifecycle hooks, guarded
        self.limits = limits
        self.renderer = renderer
        self.status = status
        self.metrics = Metrics(backend.name, getattr(backend.source, "fps", 0.0) if backend.source else 0.0,
                               input=input_of(backend))
        stage.metrics = self.metrics
        self.latest = Latest()
        self.gestures = GestureQueue()
        self._stop = threading.Event()
        self._sensor_done = threading.Event()
        self._wake = threading.Event()  # set by the sensor: new data, deliver it now
        self.sensor_error: BaseException | None = None
        self.failed_frame = 0  # the number (from 1) of the last frame the backend raised on
        self.label = label  # what is playing, for messages (a clip's path); None: the profile's source
        self.hold = hold  # True: after the sensor side ends, keep rendering until stopped (calibration)
        # True (an unpaced `--fast` show): the sensor waits until the effects saw each frame, so a
        # busy machine changes nothing in what they do (hands and gestures stay in step)
        self.lossless = lossless
        self._delivered = threading.Event()
        self._failed_in_a_row = 0

    def request_stop(self) -> None:
        """Ctrl-C, SIGTERM or a window close: stop cleanly at the next frame."""
        self._stop.set()

    # -- sensor thread -------------------------------------------------------------------------
    def _sensor(self) -> None:
        first_t: float | None = None
        seconds = self.limits.seconds
        deadline = None if seconds is None else time.monotonic() + seconds + WALL_GRACE_S
        try:
            while not self._stop.is_set():
                if deadline is not None and time.monotonic() > deadline:
                    self._check_any_frame()
                    break
                frame = self._next_frame()
                if frame is False:
                    continue
                if frame is None:  # the source ended: what the backend was still confirming completes
                    self.gestures.put_all(self.backend.finish())
                    break
                self.metrics.sensor_frame(frame)
                self.gestures.put_all(frame.gestures)
                self.latest.publish(frame)
                self._wake.set()
                if self.lossless:
                    self._await_delivery()
                first_t = frame.timestamp if first_t is None else first_t
                if self.limits.frames is not None and self.metrics.frames >= self.limits.frames:
                    break
                if seconds is not None and frame.timestamp - first_t >= seconds:
                    break
        except Exception as error:  # the backend failed: report it, end the show cleanly
            self.sensor_error = error
        finally:
            self._sensor_done.set()
            self._wake.set()

    def _check_any_frame(self) -> None:
        """Out of wall time: a show that got no frame at all ends as a missing camera does, with
        one line saying what the backend waited for (its input label: where, and what to start)."""
        if not self.metrics.frames:
            raise UserError(f"backend {self.backend.name!r}: no frame in {self.limits.seconds + WALL_GRACE_S:g} s "
                            f"(the time limit, {self.limits.seconds:g} s, plus {WALL_GRACE_S:g} s of grace); "
                            f"input: {self.metrics.input_label}")

    def _await_delivery(self) -> None:
        while not self._delivered.wait(0.1):
            if self._stop.is_set():
                return
        self._delivered.clear()

    def _next_frame(self) -> Frame | None | bool:
        """The backend's next frame; False when none came yet or it raised on this one. A backend
        that fails on a frame (an odd depth image) loses that frame and the show goes on; one that
        fails on `MAX_FAILED_IN_A_ROW` frames in a row, or reports a damaged input (UserError), ends it."""
        try:
            frame = self.backend.update()
        except UserError:
            raise
        except Exception as error:
            self._failed_in_a_row += 1
            self.metrics.failed += 1
            self.failed_frame = self.metrics.frames + self.metrics.failed
            if self._failed_in_a_row >= MAX_FAILED_IN_A_ROW:
                raise
            if self.metrics.failed == 1:
                where = f" of {self.label}" if self.label else ""
                print(f"issv: backend {self.backend.name!r} raised {type(error).__name__} on frame "
                      f"{self.failed_frame}{where}: {error}; the frame is skipped and the show goes on "
                      "(failed frames are counted in the summary)", file=sys.stderr, flush=True)
            return False
        self._failed_in_a_row = 0
        return frame

    # -- show loop -----------------------------------------------------------------------------
    def _call(self, slot: EffectSlot, phase: str, *args: Any) -> None:
        try:
            getattr(slot.effect, phase)(*args)
        except Exception as error:
            self.disable(slot, phase, error)

    def disable(self, slot: EffectSlot, phase: str, error: BaseException) -> None:
        """One failing effect is switched off with one message; the others go on."""
        slot.enabled = False
        print(f"issv: effect {slot.effect.name!r} ({slot.where}) raised {type(error).__name__} in {phase}: "
              f"{error}; it is disabled, the show goes on", file=sys.stderr, flush=True)
        if self.notify is not None:
            self.notify("effect_failed", effect=slot.effect, error=error, phase=phase)

    def _running(self) -> list[EffectSlot]:
        return [s for s in self.effects if s.enabled]

    def _deliver(self, last_count: int) -> int:
        """Event-driven: every pending gesture (all of them, in order), then the newest frame."""
        for gesture in self.gestures.drain():
            self.metrics.gesture(gesture)
            for slot in self._running():
                self._call(slot, "on_gesture", gesture)
        frame, count = self.latest.take()
        if frame is not None and count != last_count:
            for slot in self._running():
                self._call(slot, "on_frame", frame)
            self.metrics.delivered(frame, skipped=count - last_count - 1)
            self._delivered.set()
        return count

    def _render(self) -> None:
        """Paced at the output rate: draw the newest frame (or just count the tick when nothing draws)."""
        if self.renderer is not None:
            self.renderer.render(self, self.latest.take()[0])
        self.metrics.rendered_frame()
        if self.status is not None:
            self.status(self)

    def run(self) -> Metrics:
        for slot in self.effects:
            self._call(slot, "setup", self.stage)
        try:
            self.backend.init()
            try:
                self._play()
            finally:
                self.backend.stop()
        finally:
            for slot in self.effects:
                self._close(slot.effect, slot.where)
            if self.renderer is not None:
                self.renderer.close()
        return self.metrics

    def _play(self) -> None:
        if self.backend.source is not None:
            self.metrics.source_fps = float(self.backend.source.fps)
            self.metrics.source_health = self.backend.source.health
        self.backend.start_hand_tracking()
        self.backend.start_gesture_detection()
        if self.notify is not None:
            self.notify("host_started", show=self)
        sensor = threading.Thread(target=self._sensor, name="issv-sensor", daemon=True)
        sensor.start()
        try:
            self._show_loop()
        finally:
            self._stop.set()
            sensor.join(timeout=2.0)
            if self.notify is not None:
                self.notify("host_stopping", show=self)

    def _close(self, effect: Effect, where: str) -> None:
        try:
            effect.close()
        except Exception as error:
            print(f"issv: effect {effect.name!r} ({where}) raised in close: {error}", file=sys.stderr)

    def replace_effects(self, slots: list[EffectSlot]) -> None:
        """Live reload: swap in a new effect stack between two ticks (call it on the show thread,
        e.g. from the status hook). New effects come set up; effects left out are closed."""
        kept = {id(slot.effect) for slot in slots}
        old = self.effects
        for slot in old:
            if id(slot.effect) not in kept:
                self._close(slot.effect, slot.where)
        # Position i keeps its slot object: a renderer keys per-effect state (its layer) on it.
        for i, (was, now) in enumerate(zip(old, slots)):
            vars(was).update(vars(now))
            slots[i] = was
        self.effects = slots

    def _show_loop(self) -> None:
        """Deliver as soon as the sensor publishes (low latency for OSC and friends); render at the
        output rate. After the sensor ends, everything pending is delivered and rendered once more."""
        period = 1.0 / self.stage.fps
        count = rendered_count = 0
        next_render = time.perf_counter()
        while not self._stop.is_set():
            done = self._sensor_done.is_set()  # read before delivering so the last frame gets out
            self._wake.clear()
            count = self._deliver(count)
            now = time.perf_counter()
            if now >= next_render:
                self._render()
                rendered_count = count
                next_render = max(next_render + period, now)
            if done and not len(self.gestures) and self.latest.take()[1] == count:
                if rendered_count != count:
                    self._render()
                    rendered_count = count
                if not self.hold:
                    break
            if self.renderer is not None and getattr(self.renderer, "wants_stop", False):
                break
            self._wake.wait(max(0.0, next_render - time.perf_counter()))
