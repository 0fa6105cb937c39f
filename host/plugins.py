"""The plugin manager: loads entry points one at a time, collects what the hooks register.

Built-in backends, sources and effects are ordinary plugins listed in pyproject.toml under the
`issv` entry-point group, exactly as a third-party package lists its own.
"""
from __future__ import annotations

import importlib.metadata
import os
import sys
from dataclasses import dataclass
from functools import cache
from types import ModuleType
from typing import Any, Iterable

import pluggy

from host import hookspecs
from host.contracts import Backend, Effect, Plugin, Source

KINDS: dict[str, type[Plugin]] = {"backends": Backend, "sources": Source, "effects": Effect}
ENTRY_POINT_GROUP = "issv"


class PluginError(RuntimeError):
    """A plugin could not be loaded or registered (fatal only in strict mode)."""


@dataclass(frozen=True)
class Registered:
    """One registered class and the plugin that handed it over."""

    kind: str
    name: str
    cls: type[Plugin]
    plugin: str

    def availability(self) -> str | None:
        try:
            return self.cls.availability()
        except Exception as error:  # a broken availability check is itself a reason
            return f"availability check raised {type(error).__name__}: {error}"

    def to_json(self) -> dict:
        reason = self.availability()
        doc = {"name": self.name, "available": reason is None, "reason": reason, "plugin": self.plugin}
        if hasattr(self.cls, "frames"):  # a source: the frames it gives
            doc["frames"] = self.cls.frames
        elif hasattr(self.cls, "needs_source"):  # a backend: the frames it tracks, if it takes a source
            doc["frames"] = self.cls.takes if self.cls.needs_source else None
        return doc


@dataclass(frozen=True)
class RegisteredCommand:
    """One `issv` subcommand and the plugin that handed it over."""

    name: str
    command: Any  # a module or object with HELP, add_arguments(parser), main(args) -> int
    plugin: str


def command_name(command: Any) -> str:
    """A command's `NAME`, else its module's last name with `_` as `-`."""
    if hasattr(command, "NAME"):
        return command.NAME
    module = command.__name__ if isinstance(command, ModuleType) else type(command).__module__
    return module.rsplit(".", 1)[-1].replace("_", "-")


class Registry:
    """Everything registered, by kind and name; refuses duplicates with a clear message."""

    def __init__(self) -> None:
        self.items: dict[str, dict[str, Registered]] = {kind: {} for kind in KINDS}
        self.commands: dict[str, RegisteredCommand] = {}
        self.problems: list[str] = []

    def register(self, kind: str, cls: type, plugin: str) -> None:
        base = KINDS[kind]
        if not (isinstance(cls, type) and issubclass(cls, base)):
            raise PluginError(f"plugin {plugin!r} registered {cls!r} as one of its {kind}, "
                              f"but it is not a subclass of host.{base.__name__}")
        if not cls.name:
            raise PluginError(f"plugin {plugin!r}: {cls.__name__} has no `name`; set name = \"...\" on the class")
        existing = self.items[kind].get(cls.name)
        if existing is not None:
            raise PluginError(f"plugin {plugin!r} registers {kind[:-1]} {cls.name!r}, "
                              f"already registered by plugin {existing.plugin!r}; rename one of them")
        self.items[kind][cls.name] = Registered(kind, cls.name, cls, plugin)

    def register_command(self, command: Any, plugin: str) -> None:
        """A subcommand handed over by `register_commands` (see host/hookspecs.py)."""
        missing = [a for a in ("HELP", "add_arguments", "main") if not hasattr(command, a)]
        if missing:
            raise PluginError(f"plugin {plugin!r} registered command {command!r} without {', '.join(missing)}")
        name = command_name(command)
        existing = self.commands.get(name)
        if existing is not None:
            raise PluginError(f"plugin {plugin!r} registers command {name!r}, "
                              f"already registered by plugin {existing.plugin!r}; rename one of them")
        self.commands[name] = RegisteredCommand(name, command, plugin)

    def get(self, kind: str, name: str) -> Registered | None:
        return self.items[kind].get(name)

    def names(self, kind: str) -> list[str]:
        return sorted(self.items[kind])

    def all(self, kind: str) -> Iterable[Registered]:
        return (self.items[kind][n] for n in self.names(kind))


def strict() -> bool:
    return os.environ.get("ISSV_STRICT_PLUGINS", "") not in ("", "0")


def _report(message: str) -> None:
    if strict():
        raise PluginError(message + " (ISSV_STRICT_PLUGINS is set)")
    print(f"issv: {message}; skipped (set ISSV_STRICT_PLUGINS=1 to make this fatal)", file=sys.stderr)


def make_manager() -> pluggy.PluginManager:
    """A fresh plugin manager with every installed entry point loaded, broken ones skipped."""
    pm = pluggy.PluginManager("issv")
    pm.add_hookspecs(hookspecs)
    for ep in importlib.metadata.entry_points(group=ENTRY_POINT_GROUP):
        dist = ep.dist.name if ep.dist is not None else "?"
        if pm.get_plugin(ep.name) is not None:
            continue  # the same distribution seen twice on sys.path
        try:
            module = ep.load()
            pm.register(module, name=ep.name)
        except Exception as error:
            _report(f"plugin {ep.name!r} from distribution {dist!r} failed to load: "
                    f"{type(error).__name__}: {error}")
    while True:  # tox's check_pending: a misspelled hook is a start-up message, not a silent no-op
        try:
            pm.check_pending()
            return pm
        except pluggy.PluginValidationError as error:
            name = pm.get_name(error.plugin)
            pm.unregister(error.plugin)
            _report(f"plugin {name!r} implements a hook issv does not have: {error}")


def collect(pm: pluggy.PluginManager) -> Registry:
    """Ask every plugin to register its classes, one plugin at a time so one failure stays local."""
    registry = Registry()
    for kind in KINDS:
        caller = getattr(pm.hook, f"register_{kind}")
        for impl in caller.get_hookimpls():
            try:
                impl.function(register=lambda cls, _k=kind, _p=impl.plugin_name: registry.register(_k, cls, _p))
            except Exception as error:
                _report(f"plugin {impl.plugin_name!r} failed in register_{kind}: {type(error).__name__}: {error}")
    for impl in pm.hook.register_commands.get_hookimpls():
        try:
            impl.function(register=lambda command, _p=impl.plugin_name: registry.register_command(command, _p))
        except Exception as error:
            _report(f"plugin {impl.plugin_name!r} failed in register_commands: {type(error).__name__}: {error}")
    return registry


LIFECYCLE_HOOKS = ("host_started", "host_stopping", "effect_failed")


class Lifecycle:
    """Calls a lifecycle hook's implementations one at a time, in pluggy's order (last registered
    first). One that raises is named with its plugin, skipped for the rest of this show, and the
    others still run: a broken plugin cannot end a show, as a broken effect cannot."""

    def __init__(self, pm: pluggy.PluginManager) -> None:
        self.pm = pm
        self.broken: set[tuple[str, str]] = set()  # (plugin, hook)

    def __call__(self, hook: str, **kwargs: Any) -> None:
        if hook not in LIFECYCLE_HOOKS:
            raise ValueError(f"{hook!r} is not a lifecycle hook; expected one of {LIFECYCLE_HOOKS}")
        for impl in reversed(getattr(self.pm.hook, hook).get_hookimpls()):
            if (impl.plugin_name, hook) in self.broken:
                continue
            try:
                impl.function(**{name: kwargs[name] for name in impl.argnames})
            except Exception as error:
                self.broken.add((impl.plugin_name, hook))
                print(f"issv: plugin {impl.plugin_name!r} raised {type(error).__name__} in {hook}: {error}; "
                      "that hook of the plugin is skipped from now on, the show goes on", file=sys.stderr, flush=True)


@cache
def default_manager() -> pluggy.PluginManager:
    return make_manager()


def default_registry() -> Registry:
    """The registry of the installed plugins (loaded once per process)."""
    return _default_registry()


@cache
def _default_registry() -> Registry:
    return collect(default_manager())
