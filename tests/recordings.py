"""Helpers for tests that need a real recording: profiles written to disk, `issv record` run on them."""
from __future__ import annotations

import json
from pathlib import Path

from host import Frame
from host.cli import main as issv
from host.plugins import default_registry
from sources.synthetic import SyntheticOptions, SyntheticSource

# A small, noiseless, seeded synthetic performer: deterministic and cheap to render.
SYNTH = {"width": 160, "height": 120, "noise": 0, "holes": 0, "seed": 1}


def _toml(table: dict) -> str:
    return "{ " + ", ".join(f"{k} = {json.dumps(v)}" for k, v in table.items()) + " }"


def write_profile(path: Path, source: dict | None = None, backend: dict | None = None) -> Path:
    source = source or {"name": "synthetic", **SYNTH}
    backend = backend or {"name": "truth"}
    path.write_text(f"source = {_toml(source)}\nbackend = {_toml(backend)}\n[output]\nmode = \"headless\"\n")
    return path


def record_profile(profile: Path, out: Path, *limits: str) -> Path:
    """`issv record` of a profile, as fast as possible."""
    assert issv(["record", str(profile), "-o", str(out), *limits, "--fast"]) == 0
    return out


def record(tmp_path: Path, seconds: float = 4.0, name: str = "show.mcap", backend: str = "truth", **source) -> Path:
    """`issv record` of the synthetic performer tracked by `backend`, as fast as possible."""
    prof = write_profile(tmp_path / f"{name}.toml", {"name": "synthetic", **SYNTH, **source}, {"name": backend})
    return record_profile(prof, tmp_path / name, "--seconds", str(seconds))


def tracked_live(seconds: float = 4.0, backend: str = "truth", **source) -> list[Frame]:
    """What `backend` reports for the same performer when run directly (the reference)."""
    src = SyntheticSource(SyntheticOptions(**{**SYNTH, **source}))
    frames = []
    with default_registry().get("backends", backend).cls(src) as backend:
        while (frame := backend.update()) is not None:
            frames.append(frame)
            if frame.timestamp - frames[0].timestamp >= seconds:
                break
    return frames


def as_tracked(frames: list[Frame]) -> list[tuple]:
    """What must survive a recording: seq, source time, hands and gestures, exactly."""
    return [(f.seq, f.timestamp, f.hands, f.gestures) for f in frames]
