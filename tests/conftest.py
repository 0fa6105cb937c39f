"""Shared fixtures: small depth clips written to real files, in-process plugins."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

REAL_CLIPS = Path(__file__).resolve().parents[2] / "shared" / "data" / "utd-mhad-dev" / "clips"


def write_clip(path: Path, frames: int = 30, size: tuple[int, int] = (320, 240), fps: float = 30.0) -> Path:
    """A tiny valid depth clip: a flat wall at 3 m with a box moving across it."""
    w, h = size
    depth = np.full((frames, h, w), 3000, np.uint16)
    for i in range(frames):
        depth[i, h // 3: h // 2, (i * 3) % (w - 20): (i * 3) % (w - 20) + 20] = 2000
    np.savez(path, depth=depth, timestamps=np.arange(frames) / fps,
             intrinsics=np.array([w * 0.89, w * 0.89, w / 2, h / 2]), mirrored=True)
    return path


@pytest.fixture
def clip(tmp_path: Path) -> Path:
    return write_clip(tmp_path / "clip.npz")
