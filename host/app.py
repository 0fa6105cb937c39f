"""What a plugin's command needs from the host (a public host module, see host.PUBLIC_MODULES).

`SensorShow` runs a profile's source and backend through the host's frame loop with no effects,
and lets the command see every frame the backend makes, on the sensor thread, before newest-wins
can drop one: `issv record` stores them, the network backend's `issv serve` publishes them. The
pacing, limits, Ctrl-C handling, metrics, lifecycle hooks and the rules for a backend that raises
are the show's own.

`plugin_class` finds an installed source, backend or effect by name (a lookup, not an import: a
plugin never imports another), `headless_context` and `EffectCanvas` render effects offscreen
without a show (`issv isf` feeds a depth view to ISF image inputs). GL loads only when called.
"""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING, Callable

from host import profile as profiles
from host.assemble import make_backend, make_stage
from host.contracts import Backend, Effect
from host.errors import UserError
from host.loop import WALL_GRACE_S, Limits, Show
from host.metrics import Metrics
from host.model import Frame, Gesture
from host.plugins import default_manager, default_registry
from host.status import StatusLine, summary
from host.tap import SensorTap

if TYPE_CHECKING:
    import moderngl

__all__ = ["EffectCanvas", "Metrics", "SensorShow", "UserError", "add_limit_arguments", "headless_context", "plugin_class"]


def add_limit_arguments(p: argparse.ArgumentParser) -> None:
    """--frames and --seconds: when a show ends by itself (host.loop.Limits), for every command that runs one."""
    p.add_argument("--frames", type=int, metavar="N", help="stop after N sensor frames")
    p.add_argument("--seconds", type=float, metavar="S", help=f"stop after S seconds of source time, and after "
                   f"S + {WALL_GRACE_S:g} s of wall time at most (a live input that sends nothing ends too)")


def plugin_class(kind: str, name: str) -> type:
    """The installed plugin class `name` of `kind` ("sources", "backends", "effects"); UserError
    naming what is installed, or why it cannot run here."""
    registry = default_registry()
    entry = registry.get(kind, name)
    if entry is None:
        raise UserError(f"no {kind[:-1]} named {name!r}; installed: {', '.join(registry.names(kind)) or 'none'}")
    reason = entry.availability()
    if reason is not None:
        raise UserError(f"{kind[:-1]} {name!r} cannot run here: {reason}")
    return entry.cls


def headless_context() -> "moderngl.Context":
    """A standalone OpenGL 3.3 context on EGL (Mesa llvmpipe without a GPU); UserError if none."""
    from host.render.context import headless_context as make
    return make()


class EffectCanvas:
    """Draws an effect's `render(target)` for a given frame into a framebuffer of the caller's,
    with the same target (Layer) a show gives it: the frame's depth and mask textures, blending."""

    def __init__(self, ctx: "moderngl.Context", size: tuple[int, int]) -> None:
        from host.render.compositor import Layer
        from host.render.textures import FrameTextures
        self._textures = FrameTextures(ctx)
        self._layer = Layer(ctx, size, self._textures)

    def render(self, effect: Effect, frame: Frame, fbo: "moderngl.Framebuffer") -> None:
        self._textures.frame = self._layer.frame = frame
        self._layer.fbo = fbo
        self._layer.use()
        effect.render(self._layer)

    def release(self) -> None:
        self._textures.release()


class SensorShow:
    """A profile's source and backend, ready to run. `backend` is the profile's backend on its
    source (paced to real time unless `fast`); `metrics` is the live Metrics once `run` started."""

    def __init__(self, profile: str | Path, fast: bool = False) -> None:
        self.profile = profiles.load(profile)
        self.backend: Backend = make_backend(self.profile, realtime=not fast)
        self.metrics: Metrics | None = None

    @property
    def source_name(self) -> str:
        """The profile's source name ("" when its backend reads none)."""
        return self.profile.source.ref.name if self.profile.source is not None else ""

    def run(self, observe: Callable[[Frame], None], *, observe_end: Callable[[tuple[Gesture, ...]], None] | None = None,
            closed: Callable[[], None] | None = None, frames: int | None = None, seconds: float | None = None,
            status: Callable[[], str] | None = None) -> Metrics:
        """Run until the source ends, a limit is reached or Ctrl-C / SIGTERM. `observe(frame)` sees
        every frame; `observe_end(gestures)` what the backend's `finish()` completed at the end of the
        source; `closed()` runs once the backend has stopped; `status()` is a second status line.
        Prints the summary; a backend that failed raises UserError with one line saying so."""
        tap = SensorTap(self.backend, observe, closed=closed, observe_end=observe_end)
        line = StatusLine(extra=status)
        show = Show(tap, [], make_stage(self.profile, self.backend), pm=default_manager(),
                    limits=Limits(frames, seconds), status=line)
        self.metrics = show.metrics
        metrics = play(show, line)
        check_sensor(show)
        return metrics


def play(show: Show, status: StatusLine) -> Metrics:
    """Run a show: Ctrl-C and SIGTERM stop it cleanly, a live status, the summary at exit."""
    import signal

    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: show.request_stop())
    with status:
        metrics = show.run()
    summary(metrics)
    return metrics


def check_sensor(show: Show) -> None:
    """A backend that failed mid-show ends the command with one clear line."""
    err = show.sensor_error
    if isinstance(err, UserError):  # already one clear line (a damaged recording, a missing file)
        raise err
    if err is not None:
        raise UserError(f"issv: backend {show.backend.name!r} failed: {type(err).__name__}: {err}")
