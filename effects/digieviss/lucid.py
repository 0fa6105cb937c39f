"""Forensic Lucid text: the program DigiEVISS generates (thesis Listings 2.1, 4.10-4.12, 5.1)
and the observations it can preload from an existing program."""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

from host.errors import UserError

Notation = Literal["list", "fby"]

_OBSERVATION = re.compile(r"^\s*observation\s+([A-Za-z_]\w*)\s*=\s*\((.*)\)\s*;\s*$")


@dataclass(frozen=True)
class Observation:
    """One observation: its id (o0, o1, ...) and the text inside its parentheses,
    e.g. `"A printed" => "very well", 1, 0, 0.85, 1234` (property, min, max, w, t)."""

    id: str
    data: str


def quote(text: str) -> str:
    """A Forensic Lucid string literal."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def observation_data(evidence: str, value: str, min: int, max: int, w: float, t: int) -> str:
    """The tuple text of Listing 5.1: ("A printed" => "very well", 1, 0, 0.85, 1234)."""
    return f"{quote(evidence)} => {quote(value)}, {min}, {max}, {w:g}, {t}"


def sequence(ids: list[str], notation: Notation) -> str:
    """An observation sequence in list notation `{o0, o3}` or with `fby`: `o1 fby o2`."""
    return "{" + ", ".join(ids) + "}" if notation == "list" else " fby ".join(ids)


def program(observations: list[Observation], sequences: list[list[str]], notation: Notation = "list") -> str:
    """The whole program: header, every observation, the linked sequences, the evidential
    statement and the footer, shaped like Listing 5.1."""
    lines = ["es", "where"]
    lines += [f"    observation {o.id} = ({o.data});" for o in observations]
    names = [f"os{i}" for i in range(1, len(sequences) + 1)]
    lines += [f"    observation sequence {name} = {sequence(ids, notation)};" for name, ids in zip(names, sequences)]
    statement = names[0] if len(names) == 1 else "{" + ", ".join(names) + "}"
    lines += [f"    evidential statement es1 = {statement};", "end", ""]
    return "\n".join(lines)


def read_observations(path: str | Path) -> list[Observation]:
    """The `observation ID = (...);` lines of a Forensic Lucid file, in file order."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as error:
        raise UserError(f"{path}: cannot read the observations: {error}") from None
    found = [Observation(m[1], m[2].strip()) for m in map(_OBSERVATION.match, text.splitlines()) if m]
    if not found:
        raise UserError(f"{path}: no `observation oN = (...);` lines; write one observation per line as in "
                        f"Listing 5.1")
    ids = [o.id for o in found]
    twice = sorted({i for i in ids if ids.count(i) > 1})
    if twice:
        raise UserError(f"{path}: observation ids used more than once: {', '.join(twice)}")
    return found
