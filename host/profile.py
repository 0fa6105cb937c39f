"""Profiles: TOML files naming a source, a backend, a stack of effects and the output.

Validation reports every problem as one line `FILE: key.path: expected ..., got ...` so an artist
can fix a profile without reading a traceback.
"""
from __future__ import annotations

import difflib
import json
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal, get_args

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from host.errors import ProfileError
from host.plugins import Registry, default_registry


class PluginRef(BaseModel):
    """`name` picks the plugin; every other key is that plugin's option."""

    model_config = ConfigDict(extra="allow")
    name: str

    @property
    def options(self) -> dict[str, Any]:
        return dict(self.model_extra or {})


class LearnedRef(BaseModel):
    """A learned gesture in `[backend] learned`: a file, and optionally its own threshold and how
    much a performance of a gesture taught as a loop must loop (host/learned/loops.py; 0: not checked)."""

    model_config = ConfigDict(extra="forbid")
    file: str
    threshold: float | None = Field(None, gt=0)
    loop: float | None = Field(None, ge=0)


class BackendRef(PluginRef):
    """The backend; `learned` lists learned-gesture files (relative to the profile) the host
    recognises on its hands: `"file"` or `{file = "...", threshold = 0.3, loop = 0}`."""

    learned: list[str | LearnedRef] = []


class EffectRef(PluginRef):
    """An effect in the stack; the host owns how its layer is composited."""

    blend: Literal["normal", "add", "screen", "multiply"] = "normal"
    opacity: float = Field(1.0, ge=0, le=1)
    enabled: bool = True


class Output(BaseModel):
    """Where the show goes. `--headless`, `--size`, `--out` and `--snapshot` override these."""

    model_config = ConfigDict(extra="forbid")
    size: tuple[int, int] = (1280, 720)
    fps: float = Field(60.0, gt=0, le=240)
    mode: Literal["window", "fullscreen", "headless"] = "window"
    monitor: int = Field(0, ge=0)
    hud: bool = True
    video: str | None = None
    snapshot: str | None = None
    keystone: list[tuple[float, float]] | None = None
    calibration: list[list[float]] | None = None


def _shorthand(value: Any) -> Any:
    return {"name": value} if isinstance(value, str) else value


class ProfileModel(BaseModel):
    model_config = ConfigDict(extra="forbid")
    name: str = ""
    description: str = ""
    source: PluginRef = PluginRef(name="synthetic")
    backend: BackendRef = BackendRef(name="openiss")
    effects: list[EffectRef] = []
    output: Output = Output()

    _shorthands = field_validator("source", "backend", mode="before")(lambda cls, v: _shorthand(v))


@dataclass
class Resolved:
    """A plugin reference checked against the registry: its class and validated options."""

    ref: PluginRef
    cls: type
    options: BaseModel
    where: str


@dataclass
class Profile:
    path: Path
    model: ProfileModel
    source: Resolved | None
    backend: Resolved
    effects: list[Resolved]
    warnings: list[str]
    learned: list[Any] = field(default_factory=list)  # LearnedGesture, thresholds already overridden


def _path(loc: tuple) -> str:
    out = ""
    for part in loc:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out


def _got(value: Any) -> str:
    try:
        return json.dumps(value)
    except (TypeError, ValueError):
        return repr(value)


def describe(file: str, error: dict, prefix: tuple = (), allowed: list[str] | None = None) -> str:
    """One pydantic error as one line for people."""
    where = f"{file}: {_path(prefix + tuple(error['loc']))}"
    kind, msg = error["type"], error["msg"]
    if kind == "extra_forbidden":
        return f"{where}: unknown key{_keys_hint(str(error['loc'][-1]), allowed or [])}"
    if kind == "missing":
        return f"{where}: required key is missing"
    for lead, repl in (("Input should be ", "expected "), ("Value error, ", ""), ("Assertion failed, ", "")):
        if msg.startswith(lead):
            msg = repl + msg[len(lead):]
    return f"{where}: {msg}, got {_got(error.get('input'))}"


LISTED_KEYS = 12  # a table with more keys names the nearest few and where all of them are


def _keys_hint(key: str, allowed: list[str]) -> str:
    """What was meant by an unknown key: the keys allowed there, or the nearest of many."""
    if len(allowed) <= LISTED_KEYS:
        return f"; expected one of: {', '.join(allowed)}" if allowed else ""
    near = difflib.get_close_matches(key, allowed, n=3, cutoff=0.6)
    meant = f"; did you mean {', '.join(near)}?" if near else ""
    return f"{meant} ({len(allowed)} keys here: docs/profile-reference.md lists them)"


def _errors(file: str, error: ValidationError, model: type[BaseModel], prefix: tuple = ()) -> list[str]:
    return [describe(file, e, prefix, _keys_at(model, e["loc"][:-1])) for e in error.errors(include_url=False)]


def _keys_at(model: type[BaseModel], loc: tuple) -> list[str] | None:
    """The keys of the table at `loc` (an unknown key's parents): the nested model's fields, None
    where the table is no model (a dict's keys, a list's items)."""
    for part in loc:
        info = model.model_fields.get(part) if isinstance(part, str) else None
        kinds = (info.annotation, *get_args(info.annotation)) if info else ()  # X, or X | None
        nested = [t for t in kinds if isinstance(t, type) and issubclass(t, BaseModel)]
        if not nested:
            return None
        model = nested[0]
    return sorted(model.model_fields)


def _resolve(file: str, registry: Registry, kind: str, ref: PluginRef, where: tuple,
             context: dict, problems: list[str], warnings: list[str]) -> Resolved | None:
    entry = registry.get(kind, ref.name)
    label = _path(where)
    if entry is None:
        known = ", ".join(registry.names(kind)) or "none installed"
        problems.append(f"{file}: {label}.name: expected one of {known}, got {_got(ref.name)} "
                        f"(`issv list` shows what is installed)")
        return None
    reason = entry.availability()
    if reason is not None:
        line = f"{file}: {label}: {kind[:-1]} {ref.name!r} is not available here: {reason}"
        if kind == "effects":
            warnings.append(line + "; that effect is skipped")
            return None
        problems.append(line)
    try:
        options = entry.cls.Options.model_validate(ref.options, context=context)
    except ValidationError as error:
        problems.extend(_errors(file, error, entry.cls.Options, where))
        return None
    return Resolved(ref, entry.cls, options, label)


def parse(text: str, file: str, base_dir: Path, registry: Registry | None = None) -> Profile:
    """Validate a profile's text; raise ProfileError with every problem found."""
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise ProfileError([f"{file}: not valid TOML: {error}"]) from None
    try:
        model = ProfileModel.model_validate(raw)
    except ValidationError as error:
        raise ProfileError(_errors(file, error, ProfileModel)) from None
    registry = registry or default_registry()
    context = {"base_dir": base_dir}
    problems: list[str] = []
    warnings: list[str] = []
    backend = _resolve(file, registry, "backends", model.backend, ("backend",), context, problems, warnings)
    source = None
    if backend is None or backend.cls.needs_source:
        source = _resolve(file, registry, "sources", model.source, ("source",), context, problems, warnings)
    if backend is not None and source is not None and source.cls.frames != backend.cls.takes:
        problems.append(f"{file}: [backend] {backend.ref.name!r} tracks {backend.cls.takes} frames, but [source] "
                        f"{source.ref.name!r} gives {source.cls.frames} frames: pick a source with "
                        f"{backend.cls.takes} frames or a backend that takes {source.cls.frames} ones "
                        f"(`issv list` says which is which)")
    elif backend is not None and not backend.cls.needs_source and "source" in raw:
        warnings.append(f"{file}: [source] {model.source.name!r} is not used: backend {backend.ref.name!r} "
                        f"makes its own frames (it takes no source)")
    effects = []
    for i, ref in enumerate(model.effects):
        if ref.enabled:
            resolved = _resolve(file, registry, "effects", ref, ("effects", i), context, problems, warnings)
            if resolved is not None:
                effects.append(resolved)
    learned = _learned(file, model.backend, base_dir, problems)
    if problems:
        raise ProfileError(problems)
    return Profile(Path(file), model, source, backend, effects, warnings, learned)


def _learned(file: str, ref: BackendRef, base_dir: Path, problems: list[str]) -> list[Any]:
    """The profile's learned gestures, read now so that a bad file stops the show before it starts."""
    from host.errors import UserError
    from host.learned.gesture_file import load as load_gesture
    out = []
    for i, entry in enumerate(ref.learned):
        entry = LearnedRef(file=entry) if isinstance(entry, str) else entry
        try:
            gesture = load_gesture(base_dir / entry.file)
        except UserError as error:
            problems.append(f"{file}: backend.learned[{i}]: {error}")
            continue
        if entry.threshold is not None:
            gesture.threshold = entry.threshold
        gesture.loop = entry.loop
        out.append(gesture)
    return out


def load(path: str | Path, registry: Registry | None = None) -> Profile:
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ProfileError([f"{path}: no such profile (profiles/ holds the ready-to-run ones)"]) from None
    except (OSError, UnicodeDecodeError) as error:
        raise ProfileError([f"{path}: cannot read the profile: {error}"]) from None
    return parse(text, str(path), path.resolve().parent, registry)
