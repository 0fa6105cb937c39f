"""The learned-gesture file: one gesture, shareable between machines (docs/learned-gestures.md).

A small JSON document. Its repetitions are postures in body units (features.py) sampled at
`rate_hz`, so a file taught on one camera works on another. Everything the recogniser uses is in
the file and may be edited by hand: `threshold` (how close a performance must come; the profile
may override it), `fires_at` (how far into the gesture it completes) and `weights`; and, when the
artist gave any, `unlike`: whole takes of motions it must not be taken for (counter-examples).
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from host.errors import UserError

FORMAT = "issv-learned-gesture"
NUMBER = (int, float)  # what a numeric field may be in the JSON
VERSION = 1
HANDS = ("left", "right", "both")
IDLE_WEIGHT = 0.3  # an unused hand still counts this much: the rest of the body should look alike


def hand_weights(hands: str) -> np.ndarray:
    """The posture weights (left x y z, right x y z) of a gesture made with `hands`."""
    weights = np.ones(6)
    if hands == "left":
        weights[3:] = IDLE_WEIGHT
    elif hands == "right":
        weights[:3] = IDLE_WEIGHT
    return weights


@dataclass
class TaughtRepetition:
    """One repetition as taught: where it came from and its postures (n, 6)."""

    source: str
    start: float
    end: float
    postures: np.ndarray
    score: float | None = None  # its distance to the other repetitions (lower: more typical)

    @property
    def duration(self) -> float:
        return self.end - self.start


@dataclass
class LearnedGesture:
    name: str
    hands: str
    threshold: float
    fires_at: float
    weights: np.ndarray
    repetitions: list[TaughtRepetition] = field(default_factory=list)
    rate_hz: float = 15.0
    left_out: list[TaughtRepetition] = field(default_factory=list)  # found but not learned (odd length)
    found: dict[str, int] = field(default_factory=dict)  # repetitions found per example
    paces: dict[str, float] = field(default_factory=dict)  # examples learned at a pace of their own: their length (s)
    unlike: list[TaughtRepetition] = field(default_factory=list)  # counter-examples: motions it is not (whole takes)
    loop: float | None = None  # a profile's override of how much a performance must loop (loops.py); not in the file

    def with_one_arm(self, side: str) -> "LearnedGesture":
        """This two-handed gesture performed with the `side` arm alone: each repetition with the other
        hand held where it was when the repetition began (hanging at rest), weighted as unused."""
        idle = slice(3, 6) if side == "left" else slice(0, 3)
        reps = []
        for rep in self.repetitions:
            postures = rep.postures.copy()
            postures[:, idle] = postures[0, idle]
            reps.append(replace(rep, postures=postures))
        return replace(self, hands=side, weights=hand_weights(side), repetitions=reps, left_out=[], unlike=[])

    def completes_at(self, postures: int) -> int:
        """How many of a repetition's `postures` come before it completes: its template (matcher.py)."""
        return max(2, int(round(self.fires_at * postures)))

    def to_json(self) -> dict:
        return {
            "format": FORMAT, "version": VERSION, "name": self.name, "hands": self.hands,
            "threshold": round(float(self.threshold), 4), "fires_at": round(float(self.fires_at), 3),
            "rate_hz": self.rate_hz, "weights": [round(float(w), 3) for w in self.weights],
            "features": "left x y z, right x y z: hand minus torso over head-torso distance; +x performer's right",
            "repetitions": [_entry(r) for r in self.repetitions],
            **({"unlike": [_entry(u) for u in self.unlike]} if self.unlike else {}),
        }

    def save(self, path: Path) -> None:
        text = json.dumps(self.to_json(), separators=(",", ":"))
        # one repetition per line: diffable, and still one JSON document
        text = text.replace(',{"source"', ',\n{"source"').replace('"repetitions":[{', '"repetitions":[\n{')
        text = text.replace('"unlike":[{', '"unlike":[\n{')
        try:
            path.write_text(text + "\n", encoding="utf-8")
        except OSError as error:
            raise UserError(f"{path}: cannot write the learned gesture ({error.strerror})") from None


def _entry(r: TaughtRepetition) -> dict:
    return {"source": r.source, "start": round(r.start, 3), "end": round(r.end, 3),
            **({"score": round(r.score, 4)} if r.score is not None else {}),
            "postures": np.round(r.postures, 3).tolist()}


def load(path: Path | str) -> LearnedGesture:
    """Read and check a learned-gesture file; a bad one is a UserError naming the file and field."""
    path = Path(path)
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise UserError(f"{path}: no such learned-gesture file (make one with `issv learn NAME TAKE.csv`)") from None
    except (OSError, UnicodeDecodeError, ValueError) as error:
        raise UserError(f"{path}: not a learned-gesture file (JSON expected): {error}") from None
    return from_json(doc, str(path))


def _field(doc: dict, key: str, kind, where: str, check=lambda v: True, expect: str = ""):
    value = doc.get(key)
    if value is None or not isinstance(value, kind) or isinstance(value, bool) and kind is not bool \
            or not check(value):
        raise UserError(f"{where}: {key}: expected {expect or kind.__name__}, got {json.dumps(value)}")
    return value


def from_json(doc: dict, where: str) -> LearnedGesture:
    if not isinstance(doc, dict) or doc.get("format") != FORMAT:
        raise UserError(f"{where}: format: expected {FORMAT!r} (a file written by `issv learn`)")
    if doc.get("version") != VERSION:
        raise UserError(f"{where}: version: expected {VERSION}, got {json.dumps(doc.get('version'))} "
                        "(written by a newer issv? update issv)")
    name = _field(doc, "name", str, where, lambda v: v.strip() != "" and "/" not in v, "a name without /")
    hands = _field(doc, "hands", str, where, lambda v: v in HANDS, " or ".join(HANDS))
    threshold = _field(doc, "threshold", NUMBER, where, lambda v: v > 0, "a number > 0")
    fires_at = _field(doc, "fires_at", NUMBER, where, lambda v: 0 < v <= 1, "a number in (0, 1]")
    rate = _field(doc, "rate_hz", NUMBER, where, lambda v: v > 0, "a number > 0")
    weights = _field(doc, "weights", list, where, lambda v: len(v) == 6 and all(
        isinstance(w, NUMBER) and w >= 0 for w in v), "6 numbers >= 0")
    reps = _entries(_field(doc, "repetitions", list, where, lambda v: len(v) > 0, "a list of repetitions"),
                    f"{where}: repetitions")
    unlike = _entries(_field(doc, "unlike", list, where, expect="a list of counter-examples") if "unlike" in doc
                      else [], f"{where}: unlike")
    return LearnedGesture(name.strip(), hands, float(threshold), float(fires_at), np.asarray(weights, float),
                          reps, float(rate), unlike=unlike)


def _entries(items: list, at: str) -> list[TaughtRepetition]:
    """Repetitions (or counter-examples) as written by `_entry`; a bad one is a UserError naming it."""
    out = []
    for i, r in enumerate(items):
        if not isinstance(r, dict):
            raise UserError(f"{at}[{i}]: expected an object with source, start, end, postures")
        try:
            postures = np.asarray(r.get("postures"), dtype=float)
        except (TypeError, ValueError):
            postures = np.zeros((0,))
        if postures.ndim != 2 or postures.shape[1] != 6 or len(postures) < 2 or not np.all(np.isfinite(postures)):
            raise UserError(f"{at}[{i}].postures: expected rows of 6 finite numbers (at least 2 rows)")
        score = r.get("score")
        out.append(TaughtRepetition(str(r.get("source", "?")), float(r.get("start", 0.0)), float(r.get("end", 0.0)),
                                    postures, float(score) if isinstance(score, NUMBER) else None))
    return out
