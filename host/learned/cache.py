"""The classifier of a set of learned gestures, trained once per set rather than at every load.

Training (classifier.py) takes seconds of CPU, and every `issv gestures --learned`, show start and
`issv track` clip paid it again for the same files. The result depends only on the repetitions it
is trained on (in load order), on classifier.py's code and on numpy, so it is kept: in this process
(every recogniser and user built from one set shares one classifier) and on disk, in learned/ of
the user's cache (host/user_cache.py), one .npz per set named by a hash of exactly those inputs.
The gesture files are never touched: their format is shared with other machines and tools. An
entry is only a hint: one that cannot be read or does not match means training, a cache that
cannot be written means no cache, never an error. Entries hold arrays only (no pickle), so reading
one cannot run code; a read entry is the trained classifier bit for bit.

Code that changes the classifier at run time (patching classifier.py's functions) must call
`Classifier.train` itself: the key sees classifier.py's source, not its objects.
"""
from __future__ import annotations

import hashlib
import logging
import os
import tempfile
from pathlib import Path

import numpy as np

from host.learned import classifier
from host.learned.classifier import Classifier
from host.user_cache import cache_dir

FORMAT = b"issv-learned-classifier 1"  # bumped if what an entry holds changes
KEEP = 64  # entries kept on disk (about 18 KB each for six gestures), the most recently used
TRAINED: dict[str, Classifier] = {}  # trained or read in this process, by key
_ARRAYS = ("mean", "scale", "weights", "bias")


def trained(taught: list[list[np.ndarray]], unlike: list[list[np.ndarray]] | None = None) -> Classifier:
    """`Classifier.train(taught, unlike)`, from this process or the disk cache when it was trained before."""
    key = _key(taught, unlike or [])
    if key not in TRAINED:
        TRAINED[key] = _read(key, len(taught) + 1) or _train_and_keep(key, taught, unlike)
    return TRAINED[key]


def _key(taught: list[list[np.ndarray]], unlike: list[list[np.ndarray]]) -> str:
    """A hash of everything training depends on: the repetitions and counter-examples in order, the
    code, numpy. A set without counter-examples hashes as it did before they existed."""
    h = hashlib.sha256(FORMAT)
    h.update(Path(classifier.__file__).read_bytes())
    h.update(np.__version__.encode())
    for label, sets in ((b"gesture %d", taught), (b"unlike %d", [u for u in unlike if u])):
        for reps in sets:
            h.update(label % len(reps))
            for r in reps:
                r = np.ascontiguousarray(r, np.float64)
                h.update(repr(r.shape).encode() + r.tobytes())
    return h.hexdigest()


def _read(key: str, classes: int) -> Classifier | None:
    """The entry for `key` if there is a sound one (its key, the shapes for `classes` and this
    code's descriptor, finite numbers), else None."""
    d = classifier.describe_all(np.zeros((1, 6))).shape[1]
    shapes = dict(zip(_ARRAYS, [(d,), (d,), (2 * d, classes), (classes,)]))  # weights: descriptors and squares
    path = cache_dir() / "learned" / f"{key}.npz"
    try:
        with np.load(path, allow_pickle=False) as entry:
            arrays = {name: entry[name] for name in _ARRAYS}
            sound = str(entry["key"]) == key and all(
                a.shape == shapes[name] and a.dtype == np.float64 and np.isfinite(a).all() for name, a in arrays.items())
    except Exception:  # missing, truncated, not an .npz, an array missing: whatever it is, train
        return None
    if not (sound and (arrays["scale"] > 0).all()):
        return None
    try:
        os.utime(path)  # used now: pruning keeps the entries of the sets in use, however old
    except OSError:
        pass
    return Classifier(**arrays)


def _train_and_keep(key: str, taught: list[list[np.ndarray]], unlike: list[list[np.ndarray]] | None) -> Classifier:
    """Train, and write the entry (atomically: another process may be reading or writing it too)."""
    trained_now = Classifier.train(taught, unlike)
    try:
        folder = cache_dir() / "learned"
        folder.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=folder, suffix=".tmp")
        try:
            with os.fdopen(fd, "wb") as out:
                np.savez(out, key=np.array(key), **{name: getattr(trained_now, name) for name in _ARRAYS})
            os.replace(tmp, folder / f"{key}.npz")
        finally:
            Path(tmp).unlink(missing_ok=True)
        for old in sorted(folder.glob("*.npz"), key=lambda p: p.stat().st_mtime)[:-KEEP]:
            old.unlink()
    except (OSError, RuntimeError) as error:  # RuntimeError: no home folder
        logging.getLogger(__name__).debug("learned-gesture classifier not cached: %s", error)
    return trained_now
