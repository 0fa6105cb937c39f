"""Runs several backends on the identical depth of one recording and collects what each did.

The thesis could not feed NiTE2 and Nuitrack the same input (ch. 6.2); here every backend reads
the same recorded depth images, as fast as it can, one backend after the other, through the
same frame loop a show uses (so sFPS, rFPS, effective FPS and latency mean what they mean live).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from host.contracts import Backend, Stage
from host.errors import UserError
from host.loop import Limits, PacedSource, Show
from host.model import CANONICAL_GESTURES, Frame, Gesture, GestureState
from host.plugins import Registered, Registry, default_registry
from host.tap import SensorTap

AGREEMENT_WINDOW_S = 0.5  # two backends agree on a gesture: same name, spans this close in time
OUTPUT_FPS = 60.0  # the show loop's rate cap, as for a 60 Hz projector output


@dataclass
class Run:
    """One backend's pass over the recording."""

    backend: str
    dictionary: tuple[str, ...] | None = None  # canonical names it can report; None: not declared
    gestures: list[Gesture] = field(default_factory=list)
    frame_times: list[float] = field(default_factory=list)
    hands_per_frame: list[int] = field(default_factory=list)
    metrics: dict = field(default_factory=dict)
    latencies_ms: np.ndarray = field(default_factory=lambda: np.zeros(0))
    wall_s: float = 0.0
    error: str | None = None

    def observe(self, frame: Frame) -> None:
        self.frame_times.append(frame.timestamp)
        self.hands_per_frame.append(len(frame.hands))
        self.gestures.extend(frame.gestures)

    @property
    def completed(self) -> list[Gesture]:
        return [g for g in self.gestures if g.state is GestureState.COMPLETE]

    @property
    def hands_fraction(self) -> float:
        return float(np.mean(np.array(self.hands_per_frame) > 0)) if self.hands_per_frame else 0.0

    def counts(self) -> dict[str, int]:
        out = dict.fromkeys(CANONICAL_GESTURES, 0)
        for g in self.completed:
            out[g.name] += 1
        return out


@dataclass(frozen=True)
class Occurrence:
    """One completed gesture and the span it took: from its IN_PROGRESS event, if it had one."""

    name: str
    start: float
    end: float


def occurrences(gestures: list[Gesture]) -> list[Occurrence]:
    out, begun = [], {}
    for g in gestures:
        key = (g.type, g.hand_id)
        if g.state is GestureState.IN_PROGRESS:
            begun.setdefault(key, g.timestamp)
        else:
            out.append(Occurrence(g.name, begun.pop(key, g.timestamp), g.timestamp))
    return out


def agreement(a: list[Gesture], b: list[Gesture], window: float = AGREEMENT_WINDOW_S) -> tuple[int, float | None]:
    """Gestures two backends both saw, and the Dice score 2 * matches / (completed in a + in b);
    None when neither completed any. Two completed gestures match (each at most once) when they
    have the same canonical name and their spans, widened by `window` seconds, overlap: a backend
    that completes a wave half-way through it agrees with one that completes it at the end."""
    mine, theirs = occurrences(a), occurrences(b)
    if not mine and not theirs:
        return 0, None
    unused = list(theirs)
    matches = 0
    for g in mine:
        best = min((o for o in unused if o.name == g.name and o.start - window <= g.end and g.start - window <= o.end),
                   key=lambda o: abs(o.end - g.end), default=None)
        if best is not None:
            unused.remove(best)
            matches += 1
    return matches, 2 * matches / (len(mine) + len(theirs))


def backend_entry(registry: Registry, name: str) -> Registered:
    """The registered backend named in --backends, or a UserError listing the installed ones."""
    entry = registry.get("backends", name)
    if entry is None:
        raise UserError(f"--backends: unknown backend {name!r}; installed: {', '.join(registry.names('backends'))}")
    return entry


def make(registry: Registry, name: str, recording: Path) -> Backend:
    """The named backend with its default options on the recording, unpaced: the recording's own
    frames if the backend plays recordings itself (Backend.for_recording), else the recording's
    depth from the first source that reads recordings (Source.for_recording)."""
    entry = backend_entry(registry, name)
    reason = entry.availability()
    if reason is not None:
        raise UserError(f"backend {name!r} is not available here: {reason}")
    cls = entry.cls
    own = cls.for_recording(recording)
    if own is not None:
        return own
    if not cls.needs_source:
        raise UserError(f"backend {name!r} does not read depth, so it cannot be fed the recording")
    source = next((s for r in registry.all("sources") if (s := r.cls.for_recording(recording)) is not None), None)
    if source is None:
        raise UserError(f"no installed source reads issv recordings, so backend {name!r} cannot be fed "
                        f"{recording}; installed: {', '.join(registry.names('sources'))}")
    return cls(PacedSource(source, realtime=False), cls.Options())


def run_backend(name: str, recording: Path, progress: Callable[[Show], None] | None = None,
                registry: Registry | None = None) -> Run:
    """One backend over the whole recording; a failure is recorded in the Run, never raised."""
    registry = registry or default_registry()
    entry = registry.get("backends", name)
    declared = entry.cls.dictionary if entry is not None else None
    run = Run(name, tuple(sorted(declared)) if declared is not None else None)
    start = time.perf_counter()
    try:
        backend = make(registry, name, recording)
        tap = SensorTap(backend, run.observe, observe_end=run.gestures.extend)
        show = Show(tap, [], Stage((640, 480), OUTPUT_FPS, name), limits=Limits(), status=progress)
        metrics = show.run()
        if show.sensor_error is not None:
            raise show.sensor_error
    except Exception as error:  # one failing backend must not end the comparison
        run.error = f"{type(error).__name__}: {error}" if not isinstance(error, UserError) else str(error)
        return run
    finally:
        run.wall_s = time.perf_counter() - start
    run.metrics = metrics.to_json()
    run.latencies_ms = np.frombuffer(metrics.latencies_ms, dtype=np.float64).copy()
    return run
