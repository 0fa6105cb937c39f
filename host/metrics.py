"""What the host measures: sFPS, rFPS, effective FPS (thesis eq. 1), latency, drops, gestures."""
from __future__ import annotations

import time
from array import array
from collections import Counter, deque
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from host.model import Frame, Gesture, GestureState


def input_of(backend: Any) -> Callable[[], str]:
    """Where a backend's data comes from, said anew each time (the HUD and the status line): the
    backend's own `input_label()` if it has one (an OSC port and its message rate), else its
    source and the source's rate."""
    own = getattr(backend, "input_label", None)
    if callable(own):
        return own
    source = getattr(backend, "source", None)
    text = f"source {source.name} {source.fps:.0f} Hz" if source is not None else "its own frames"
    return lambda: text


def _rate(count: int, first: float | None, last: float | None) -> float:
    """Events per second between the first and the last event."""
    if count < 2 or first is None or last is None or last <= first:
        return 0.0
    return (count - 1) / (last - first)


@dataclass
class Metrics:
    """Counted by the sensor thread (frames) and the show loop (renders, deliveries).

    Each counter has one writer thread, so no lock is needed; readers may see a value one frame old.
    """

    backend: str
    source_fps: float
    frames: int = 0
    rendered: int = 0
    dropped: int = 0
    failed: int = 0  # frames the backend raised on (skipped; the show went on)
    gestures_by_name: Counter = field(default_factory=Counter)
    latencies_ms: array = field(default_factory=lambda: array("d"))
    _first_frame: float | None = None
    _last_frame: float | None = None
    _first_render: float | None = None
    _last_render: float | None = None
    _recent_frames: deque = field(default_factory=lambda: deque(maxlen=64))
    _recent_renders: deque = field(default_factory=lambda: deque(maxlen=128))
    last_gestures: deque = field(default_factory=lambda: deque(maxlen=5))
    source_health: Callable[[], str | None] | None = None  # a live source's own rate, drops, state

    def source_line(self) -> str:
        """What the source says about itself (a camera: its rate, dropped frames, whether it is there)."""
        said = self.source_health() if self.source_health is not None else None
        return said or f"source {self.source_fps:5.1f} Hz"

    input: Callable[[], str] | None = field(default=None, repr=False)  # see input_of()

    @property
    def input_label(self) -> str:
        """Where the data comes from and at what rate, e.g. `source synthetic 30 Hz`."""
        return self.input() if self.input is not None else ""

    def sensor_frame(self, frame: Frame) -> None:
        now = time.time()
        self.frames += 1
        self._first_frame = self._first_frame or now
        self._last_frame = now
        self._recent_frames.append(now)

    def delivered(self, frame: Frame, skipped: int) -> None:
        """The show loop handed `frame` to the effects; `skipped` newer-wins frames never reached them."""
        self.dropped += skipped
        self.latencies_ms.append((time.time() - frame.capture_time) * 1000.0)

    def gesture(self, gesture: Gesture) -> None:
        if gesture.state is GestureState.COMPLETE:
            self.gestures_by_name[gesture.name] += 1
            self.last_gestures.append(gesture)

    def rendered_frame(self) -> None:
        now = time.time()
        self.rendered += 1
        self._first_render = self._first_render or now
        self._last_render = now
        self._recent_renders.append(now)

    @property
    def sfps(self) -> float:
        return _rate(self.frames, self._first_frame, self._last_frame)

    @property
    def rfps(self) -> float:
        return _rate(self.rendered, self._first_render, self._last_render)

    @property
    def effective_fps(self) -> float:
        return (self.sfps + self.rfps) / 2

    def live(self) -> tuple[float, float]:
        """sFPS and rFPS over the last second or two, for the status line and the HUD."""
        f, r = self._recent_frames, self._recent_renders
        return (_rate(len(f), f[0] if f else None, f[-1] if f else None),
                _rate(len(r), r[0] if r else None, r[-1] if r else None))

    def latency(self, recent: int | None = None) -> dict[str, float]:
        # A slice is a copy, made under the GIL: a numpy view would pin the buffer, and the show
        # loop appending meanwhile raises BufferError (the recorder reads metrics on its own thread).
        data = np.frombuffer(self.latencies_ms[-recent:] if recent else self.latencies_ms[:], dtype=np.float64)
        if data.size == 0:
            return {"p50": 0.0, "p95": 0.0, "p99": 0.0}
        p50, p95, p99 = np.percentile(data, [50, 95, 99])
        return {"p50": float(p50), "p95": float(p95), "p99": float(p99)}

    @property
    def gestures(self) -> int:
        return sum(self.gestures_by_name.values())

    def to_json(self) -> dict:
        """The `--metrics-json` document (its keys are an interface: keep them)."""
        return {
            "backend": self.backend,
            "source_fps": round(self.source_fps, 3),
            "sfps": round(self.sfps, 3),
            "rfps": round(self.rfps, 3),
            "effective_fps": round(self.effective_fps, 3),
            "latency_ms": {k: round(v, 3) for k, v in self.latency().items()},
            "frames": self.frames,
            "dropped": self.dropped,
            "gestures": self.gestures,
            "gestures_by_name": dict(sorted(self.gestures_by_name.items())),
        }
