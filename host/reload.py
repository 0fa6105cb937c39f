"""Live reload during `issv run`: edit the profile or an effect's source and the show goes on.

The show loop calls the reloader between ticks (it rides on the status hook), so effects are
swapped at a tick boundary on the show thread, where the GL context lives. Four times a second it
compares the watched files' modification times and sizes (a few stat calls); on a change it
re-imports the changed effect modules, re-validates the profile, sets up the new effects and
only then swaps them in. Anything that fails on the way (a syntax error, a bad profile value,
a raising `setup`) is reported in one line and the previous version keeps running. An empty profile
is one being saved (truncated, not yet written) and waits for the next check.

Backend, source and output are chosen when the show starts: changing them waits for the next
start (a backend or source edit says so). Effects whose class and options did not change keep
running untouched, with their state; rebuilt ones start over.
"""
from __future__ import annotations

import dataclasses
import importlib
import importlib.util
import sys
import time
from pathlib import Path
from types import ModuleType
from typing import Any, Callable, Iterable

from host.contracts import Effect
from host.errors import ProfileError
from host.loop import EffectSlot
from host.plugins import KINDS, Registry, default_registry
from host.profile import Profile, load

Signature = tuple[int, int] | None  # (mtime in ns, size) of a file; None: it is missing


def signature(path: Path) -> Signature:
    try:
        st = path.stat()
    except OSError:
        return None
    return (st.st_mtime_ns, st.st_size)


def module_group(cls: type, others: Iterable[type]) -> str:
    """The modules reloaded together with a plugin class: the largest package around its module
    that holds no other plugin (effects.digieviss.effect -> effects.digieviss, since `effects`
    holds the other built-ins; an installed package issv_glow with issv_glow/effect.py ->
    issv_glow), else just its module (effects.console)."""
    taken = [o.__module__ for o in others if o is not cls]
    parts = cls.__module__.split(".")
    group = cls.__module__
    for i in range(len(parts) - 1, 0, -1):
        candidate = ".".join(parts[:i])
        if any(m == candidate or m.startswith(candidate + ".") for m in taken):
            break
        group = candidate
    return group


def group_modules(group: str) -> list[ModuleType]:
    """The group's loaded modules, dependencies first: the import system moves a module to the end
    of sys.modules when it has finished executing, so modules appear after those they import."""
    return [m for name, m in list(sys.modules.items())
            if (name == group or name.startswith(group + ".")) and getattr(m, "__file__", None)]


def _forget_bytecode(module: ModuleType) -> None:
    """Drop the module's cached bytecode: it is checked by whole-second mtime and size, so an edit
    saved within the same second at the same length would otherwise load the old code."""
    try:
        Path(importlib.util.cache_from_source(module.__file__)).unlink(missing_ok=True)
    except (NotImplementedError, ValueError, OSError):
        pass  # no cache for this module (or a read-only one): nothing stale to drop


class ReloadError(Exception):
    """A reload step failed; the message is the one line shown to the artist."""


def reload_group(group: str) -> None:
    """Re-import the group's modules; on any error put every one of them back as it was."""
    saved: list[tuple[ModuleType, dict[str, Any]]] = []
    try:
        for module in group_modules(group):
            saved.append((module, dict(module.__dict__)))
            _forget_bytecode(module)
            importlib.reload(module)
    except Exception as error:
        for module, namespace in saved:
            module.__dict__.clear()
            module.__dict__.update(namespace)
            sys.modules[module.__name__] = module
        where = f" ({error.filename}, line {error.lineno})" if isinstance(error, SyntaxError) else ""
        raise ReloadError(f"{group}: {type(error).__name__}: {getattr(error, 'msg', error)}{where}") from None


def _quietly_close(effect: Effect) -> None:
    """Close an effect that never went on stage; its own error was already reported."""
    try:
        effect.close()
    except Exception:
        pass


class Reloader:
    """Call it with the show between ticks; it checks the files at most every `interval` s."""

    def __init__(self, profile: Profile, registry: Registry | None = None, interval: float = 0.25,
                 say: Callable[[str], None] | None = None) -> None:
        self.profile = profile
        self.registry = registry or default_registry()
        self.interval = interval
        self.say = say or (lambda line: print(line, file=sys.stderr, flush=True))
        self._next = 0.0
        self._watched: list[Path] = []
        # the signature of each file as last loaded, kept when it leaves the watch (an effect taken out of
        # the profile): put back in, an edit made to its source meanwhile is still a change
        self._loaded: dict[Path, Signature] = {}
        self._groups: dict[Path, str] = {}
        self._watch(profile)

    def _group_of(self, cls: type) -> str:
        return module_group(cls, (e.cls for kind in KINDS for e in self.registry.all(kind)))

    def _watch(self, profile: Profile) -> None:
        """Watch the profile and the source files of every effect class it uses."""
        files: dict[Path, str] = {}
        for resolved in profile.effects:
            group = self._group_of(resolved.cls)
            for module in group_modules(group):
                files[Path(module.__file__).resolve()] = group
        self._groups = files
        self._watched = [profile.path.resolve(), *files]
        for path in self._watched:
            self._loaded.setdefault(path, signature(path))

    def __call__(self, show: Any) -> None:
        now = time.monotonic()
        if now < self._next:
            return
        self._next = now + self.interval
        now_seen = {p: signature(p) for p in self._watched}
        changed = {p for p, sig in now_seen.items() if sig != self._loaded[p]}
        profile_now = now_seen[self._watched[0]]
        if not changed or (profile_now is not None and profile_now[1] == 0):
            return  # an empty profile is one being saved (truncated, not yet written): no show to load
        for path in changed:  # a broken edit is tried once; the next save tries again
            self._loaded[path] = now_seen[path]
        try:
            self.reload(show, changed)
        except ProfileError as error:
            more = f" (and {len(error.lines) - 1} more)" if len(error.lines) > 1 else ""
            self._failed(f"{error.lines[0]}{more}")
        except ReloadError as error:
            self._failed(str(error))
        except Exception as error:  # e.g. a plugin's option validator raising: the show goes on
            self._failed(f"{type(error).__name__}: {error}")

    def _failed(self, why: str) -> None:
        """One line, whatever the error looked like (shader compilers write whole paragraphs)."""
        self.say("issv: reload failed, the previous version keeps running: " + " ".join(why.split()))

    def reload(self, show: Any, changed: set[Path]) -> None:
        groups = sorted({self._groups[p] for p in changed if p in self._groups})
        for group in groups:
            reload_group(group)
            self._adopt(group)
        profile = load(self.profile.path, self.registry)
        for warning in profile.warnings:
            self.say(f"issv: {warning}")
        old = self.profile.model
        if (profile.model.backend, profile.model.source) != (old.backend, old.source):
            self.say("issv: the backend and source are chosen at start: that change waits for the next start")
        slots, rebuilt = self._build(show, profile)
        show.replace_effects(slots)
        self.profile = profile
        self._watch(profile)
        kept = len(slots) - rebuilt
        self.say(f"issv: reloaded {', '.join(groups) or profile.path.name}: {rebuilt} effect(s) rebuilt, {kept} kept")

    def _adopt(self, group: str) -> None:
        """Point the registry at the reloaded classes, so profiles resolve to the new code."""
        for entry in list(self.registry.all("effects")):
            if self._group_of(entry.cls) != group:
                continue
            new = getattr(sys.modules[entry.cls.__module__], entry.cls.__qualname__, None)
            if not (isinstance(new, type) and issubclass(new, Effect) and new.name == entry.name):
                raise ReloadError(f"{group}: effect {entry.name!r} is no longer defined as "
                                  f"{entry.cls.__module__}.{entry.cls.__qualname__} with name {entry.name!r}")
            self.registry.items["effects"][entry.name] = dataclasses.replace(entry, cls=new)

    def _build(self, show: Any, profile: Profile) -> tuple[list[EffectSlot], int]:
        """The new stack: running effects whose class and options are unchanged are kept as they
        are; the others are made and set up now. Nothing is swapped if one fails to set up."""
        spare = [s for s in show.effects if s.enabled]
        slots: list[EffectSlot] = []
        made: list[Effect] = []
        for r in profile.effects:
            same = next((s for s in spare if type(s.effect) is r.cls and s.effect.options == r.options), None)
            if same is not None:
                spare.remove(same)
                effect = same.effect
            else:
                effect = r.cls(r.options)
                try:
                    effect.setup(show.stage)
                except Exception as error:
                    for new in made + [effect]:
                        _quietly_close(new)
                    raise ReloadError(f"effect {r.ref.name!r} ({r.where}) raised {type(error).__name__} "
                                      f"in setup: {error}") from None
                made.append(effect)
            slots.append(EffectSlot(effect, r.where, r.ref.blend, r.ref.opacity))
        return slots, len(made)
