"""Turns a validated profile into live objects: source -> backend -> effect stack."""
from __future__ import annotations

from host.contracts import Backend, Source, Stage
from host.learned_users import LearnedByUser
from host.loop import EffectSlot, PacedSource
from host.profile import Profile


def make_backend(profile: Profile, realtime: bool = True) -> Backend:
    """The profile's backend on its source (paced to real time unless `realtime` is False)."""
    source: Source | PacedSource | None = None
    if profile.backend.cls.needs_source and profile.source is not None:
        source = PacedSource(profile.source.cls(profile.source.options), realtime)
    backend = profile.backend.cls(source, profile.backend.options)
    if profile.learned:  # learned gestures: recognised by the host on this backend's hands (per user)
        return LearnedByUser(backend, profile.learned)
    return backend


def make_effects(profile: Profile) -> list[EffectSlot]:
    return [EffectSlot(r.cls(r.options), r.where, r.ref.blend, r.ref.opacity) for r in profile.effects]


def make_stage(profile: Profile, backend: Backend) -> Stage:
    """The stage of the profile's [output] (as the command line left it) for `backend`."""
    output = profile.model.output
    return Stage(size=tuple(output.size), fps=output.fps, backend=backend.name)
