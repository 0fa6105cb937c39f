"""The hook specifications: registration at start-up, lifecycle notifications. Nothing per frame.

Frames never travel through pluggy: one raising hookimpl aborts a whole hook call and the order
across plugins is not defined, so the host calls the collected objects itself, in profile order.
The lifecycle hooks are called one implementation at a time (host.plugins.Lifecycle): one that
raises is named, skipped for the rest of the show, and the show goes on, as with a broken effect.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Callable

import pluggy

if TYPE_CHECKING:  # the loop imports the contracts, not the hook specifications
    from host.contracts import Effect
    from host.loop import Show

hookspec = pluggy.HookspecMarker("issv")
hookimpl = pluggy.HookimplMarker("issv")

Register = Callable[[type], None]


@hookspec
def register_backends(register: Register) -> None:
    """Hand over Backend classes: `register(MyBackend)`."""


@hookspec
def register_sources(register: Register) -> None:
    """Hand over Source classes: `register(MySource)`."""


@hookspec
def register_effects(register: Register) -> None:
    """Hand over Effect classes: `register(MyEffect)`."""


@hookspec
def register_commands(register: Callable[[Any], None]) -> None:
    """Hand over `issv` subcommands: `register(module)`, where the module (or any object) has
    `HELP` (one line), `add_arguments(parser)` and `main(args) -> int`, and optionally `NAME`
    (default: the module's last name with `_` as `-`). Keep such modules light to import: every
    `issv` call imports them; import what the command needs inside `main`."""


@hookspec
def host_started(show: Show) -> None:
    """The show is running: source opened, backend initialised and started, effects set up; the
    sensor thread starts right after. `show.backend`, `show.stage` and `show.metrics` are there to
    read (do not change them). Called on the show's thread, once per show."""


@hookspec
def host_stopping(show: Show) -> None:
    """The show is about to stop (its source ended, a limit was reached, or Ctrl-C): the sensor
    thread has ended, the backend is not stopped yet; `show.metrics` holds the final figures and
    `show.sensor_error` is the backend's failure (or a UserError: no frame came within the time
    limit), if any. Called once per show that started."""


@hookspec
def effect_failed(effect: Effect, error: BaseException, phase: str) -> None:
    """`effect` raised `error` in `phase` (setup, on_gesture, on_frame, render) and was disabled
    for the rest of the show; the other effects go on."""
