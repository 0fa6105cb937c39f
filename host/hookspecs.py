"""The hook specifications: registration at start-up, lifecycle notifications. Nothing per frame.

Frames never travel through pluggy: one raising hookimpl aborts a whole hook call and the order
across plugins is not defined, so the host calls the collected objects itself, in profile order.
"""
from __future__ import annotations

from typing import Any, Callable

import pluggy

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
def host_started(show: Any) -> None:
    """The show is running: sources opened, backend initialised, effects set up."""


@hookspec
def host_stopping(show: Any) -> None:
    """The show is about to stop; `show.metrics` holds the final figures."""


@hookspec
def effect_failed(effect: Any, error: BaseException, phase: str) -> None:
    """An effect raised in `phase` (setup, on_gesture, on_frame, render) and was disabled."""
