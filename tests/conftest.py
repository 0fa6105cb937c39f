"""Shared fixtures: small depth clips written to real files, the real data sets (ISSV_DATA)."""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

DATA_ENV = "ISSV_DATA"
NO_DATA = f"needs the real recordings: set {DATA_ENV} to the data folder (.ci/run sets it to ../shared/data)"


def data_root() -> Path | None:
    """The folder of real data sets named by $ISSV_DATA, or None when it is unset or not a folder."""
    value = os.environ.get(DATA_ENV, "").strip()
    return Path(value) if value and Path(value).is_dir() else None


def real_data(*parts: str) -> Path:
    """A file or folder of the real data sets (e.g. `real_data("utd-mhad-dev", "clips")`).

    Without $ISSV_DATA the calling test is skipped, always with the one reason NO_DATA; with it,
    a missing part fails the test naming the path (the data folder is incomplete)."""
    root = data_root()
    if root is None:
        pytest.skip(NO_DATA)
    path = root.joinpath(*parts)
    if not path.exists():
        pytest.fail(f"{path} is missing from {DATA_ENV}={root}; see that folder's README.md")
    return path


@pytest.fixture(scope="session", autouse=True)
def own_cache(tmp_path_factory: pytest.TempPathFactory):
    """The tests' own cache folder (and their commands'): none writes the user's (host/learned/cache.py)."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("ISSV_CACHE_DIR", str(tmp_path_factory.mktemp("cache")))
        yield


@pytest.fixture
def issv_data() -> Path:
    """The real data folder ($ISSV_DATA); the test is skipped without it."""
    return real_data()


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
