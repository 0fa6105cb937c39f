"""issv's folder in the user's cache: what is worth keeping between runs but can be made again
(the learned-gesture classifiers, host/learned/cache.py; the OpenNI2 runtime's links, host/devices.py)."""
from __future__ import annotations

import os
from pathlib import Path


def cache_dir() -> Path:
    """$ISSV_CACHE_DIR (the tests set it), else issv/ in $XDG_CACHE_HOME or ~/.cache."""
    if os.environ.get("ISSV_CACHE_DIR"):
        return Path(os.environ["ISSV_CACHE_DIR"])
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "issv"
