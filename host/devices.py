"""The OpenNI2 runtime, found once for every plugin that opens OpenNI2 devices or files (a public
host module, see host.PUBLIC_MODULES): the `oni` source and the NiTE2 backend share it here rather
than import each other.

The PyPI `openni` bindings look for an unversioned `libOpenNI2.so` in a directory; Debian ships
only `libOpenNI2.so.0` with its drivers in `OpenNI2/Drivers` beside it, so when no unversioned
library exists a small directory of symbolic links (the library and its drivers folder) is made
in the user's cache and handed to `openni2.initialize`.
"""
from __future__ import annotations

import os
import tempfile
from pathlib import Path

from host.user_cache import cache_dir

LIB = "libOpenNI2.so"
LIB_DIRS = ["/usr/lib/x86_64-linux-gnu", "/usr/lib/aarch64-linux-gnu", "/usr/lib", "/usr/local/lib"]
INSTALL = "on Debian/Ubuntu: apt-get install libopenni2-0 (or set OPENNI2_REDIST to an OpenNI2 Redist folder)"


def find_runtime() -> Path | None:
    """The OpenNI2 library: $OPENNI2_REDIST first, then the system's library folders."""
    dirs = [os.environ["OPENNI2_REDIST"]] if os.environ.get("OPENNI2_REDIST") else []
    for folder in dirs + LIB_DIRS:
        for name in (LIB, LIB + ".0"):
            if (Path(folder) / name).is_file():
                return Path(folder) / name
    return None


def bindings_dir(library: Path) -> Path:
    """A folder holding an unversioned libOpenNI2.so (what the `openni` bindings load) whose
    `OpenNI2/Drivers` is the runtime's own (where OpenNI2 looks for its device drivers)."""
    if library.name == LIB:
        return library.parent
    cache = cache_dir() / "openni2"
    try:
        cache.mkdir(parents=True, exist_ok=True)
    except OSError:
        cache = Path(tempfile.mkdtemp(prefix="issv-openni2-"))
    for link, target in ((cache / LIB, library), (cache / "OpenNI2", library.parent / "OpenNI2")):
        if not (link.is_symlink() and Path(os.readlink(link)) == target):
            link.unlink(missing_ok=True)
            link.symlink_to(target)
    return cache
