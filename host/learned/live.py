"""Live teaching: repetitions taken from a profile's source and backend (camera, recording, network).

For each repetition: a count-in while the performer stands at rest, then a few seconds to perform
it once, from rest back to rest. The take is checked at once (exactly one repetition in it); a
take without one is redone, and at a terminal the artist may also discard a take and redo it.
"""
from __future__ import annotations

import sys
import time
from typing import Callable, TextIO

from host.contracts import Backend, frames_of
from host.errors import UserError
from host.learned.features import performer_body, postures
from host.learned.learner import Take, repetitions

COUNT_IN_S = 2.0  # standing at rest before each repetition (also the rest the learner needs)
MAX_TRIES = 3  # takes without a repetition in a row before giving up
BAR_WIDTH = 20


def _frames(backend: Backend, seconds: float, tick: Callable[[float], None], mirrored: list[bool]) -> list:
    """The backend's frames for `seconds` of source time; `tick(share done)` as they come;
    `mirrored[0]` follows the depth frames' own flag."""
    out, start = [], None
    for frame in frames_of(backend):
        if frame.depth is not None:
            mirrored[0] = frame.depth.mirrored
        t = frame.timestamp if frame.depth is not None else frame.capture_time
        start = t if start is None else start
        out.append((t, frame.hands, performer_body(frame)))
        tick(min(1.0, (t - start) / seconds))
        if t - start >= seconds:
            return out
    raise UserError("the source ended before the repetitions were taken; use a longer recording or a camera")


def _bar(out: TextIO, label: str) -> Callable[[float], None]:
    """A bar redrawn at a terminal as it fills (not once a frame); elsewhere (a log, a pipe) the
    label once, as `\r` redraws would fill a log with 30 lines a second."""
    shown = -1
    live = out.isatty()

    def tick(share: float) -> None:
        nonlocal shown
        filled = int(share * BAR_WIDTH)
        if filled == shown or (shown >= 0 and not live):
            return
        shown = filled
        out.write(f"\r{label} [{'#' * filled:<{BAR_WIDTH}}]" if live else label)
        out.flush()
    return tick


def teach(backend: Backend, count: int, seconds: float, out: TextIO = sys.stdout,
          ask: Callable[[str], str] | None = None) -> list[Take]:
    """`count` takes holding one repetition each. `ask(prompt)` (a terminal's input) lets the artist
    discard a take: an answer starting with r redoes it."""
    takes: list[Take] = []
    tries = 0
    mirrored = [True]  # a network or replay backend without depth: its hands come mirrored
    # named by the session: taught more live on top of a file taught live, repetitions keep apart
    session = time.strftime("live %Y-%m-%d %H:%M:%S")
    while len(takes) < count:
        n = len(takes) + 1
        rest = _frames(backend, COUNT_IN_S, _bar(out, f"repetition {n}/{count}: stand still, hands down"), mirrored)
        out.write("\n")
        motion = _frames(backend, seconds, _bar(out, f"repetition {n}/{count}: go!"), mirrored)
        out.write("\n")
        t, p = postures(rest + motion + _frames(backend, 0.5, lambda share: None, mirrored), mirrored[0])
        take = Take(f"{session} repetition {n}", t, p)
        found = repetitions(take) if len(t) > 2 else []
        if len(found) != 1:
            tries += 1
            out.write(f"  {len(found)} repetitions in that take (expected one, from rest back to rest); again\n")
            if tries >= MAX_TRIES:
                raise UserError(f"no clear repetition in {MAX_TRIES} takes in a row: are both hands in view, "
                                "and still before and after the gesture?")
            continue
        tries = 0
        answer = ask(f"  {found[0].duration:.1f} s. Enter keeps it, r redoes it: ") if ask is not None else ""
        if answer.strip().lower().startswith("r"):
            continue
        takes.append(take)
    return takes
