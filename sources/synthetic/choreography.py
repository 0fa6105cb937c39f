"""Choreographies: steps (from a profile or a TOML file) -> postures over time + truth intervals.

A step is a table such as {action = "wave", hand = "right", duration = 2.0}. Steps play one
after the other; `duration` is in seconds at speed 1 and defaults to the action's natural length
(a longer one holds still at the end; a wave fills it with more oscillations). Walk steps need
`x_mm`, where to go (camera x: towards the image's right). `speed` scales the whole timeline.
"""
from __future__ import annotations

import bisect
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from host import Side, TruthGesture
from host.errors import UserError
from sources.synthetic.motions import WALK_MAX_MM_S, HandMotion, Walk, hand_motion, min_length, walk_length
from sources.synthetic.performer import SIDES, Body, Posture

Action = Literal["idle", "wave", "click", "hand_raise", "swipe_left", "swipe_right", "swipe_up", "swipe_down", "walk"]
IDLE_S = 2.0
SWAY_MM, SWAY_HZ = 8.0, 0.23  # a person standing still is never quite still


class Step(BaseModel):
    """One entry of a choreography."""

    model_config = ConfigDict(extra="forbid")
    action: Action
    hand: Literal["left", "right"] | None = None
    duration: float | None = Field(None, gt=0, description="seconds at speed 1")
    x_mm: float | None = None

    @model_validator(mode="after")
    def _consistent(self) -> "Step":
        if self.action == "walk":
            if self.x_mm is None:
                raise ValueError("a walk needs x_mm, where to walk to (mm, towards the image's right)")
        elif self.x_mm is not None:
            raise ValueError(f"x_mm is only for walk steps, not {self.action}")
        if self.hand is not None and self.action in ("idle", "walk"):
            raise ValueError(f"{self.action} uses no particular hand; remove `hand`")
        shortest = min_length(self.action)
        if self.duration is not None and self.duration < shortest:
            raise ValueError(f"{self.action} takes at least {shortest:.2f} s at speed 1; "
                             f"duration = {self.duration:g} is too short")
        return self


def load_file(path: str | Path) -> list[Step]:
    """Steps from a TOML file holding a `steps` list; UserError naming the file and step."""
    path = Path(path)
    try:
        raw = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise UserError(f"{path}: no such choreography file") from None
    except (OSError, UnicodeDecodeError) as error:
        raise UserError(f"{path}: cannot read the choreography: {error}") from None
    except tomllib.TOMLDecodeError as error:
        raise UserError(f"{path}: not valid TOML: {error}") from None
    steps = raw.get("steps")
    if not isinstance(steps, list) or not steps or not all(isinstance(s, dict) for s in steps):
        raise UserError(f'{path}: expected a `steps` list of tables such as [[steps]] action = "wave", '
                        f"got {type(steps).__name__ if steps is not None else 'none'}")
    return parse_steps(steps, str(path))


def parse_steps(raw: list[dict], origin: str) -> list[Step]:
    """Validates steps; one UserError line per problem, `origin: steps[i].key: what is wrong`."""
    steps, problems = [], []
    for i, item in enumerate(raw):
        try:
            steps.append(Step.model_validate(item))
        except ValidationError as error:
            for e in error.errors(include_url=False):
                key = "".join(f".{part}" for part in e["loc"] if isinstance(part, str))
                msg = e["msg"].removeprefix("Value error, ").replace("Input should be", "expected")
                got = "" if e["type"] in ("value_error", "missing") else f", got {e.get('input')!r}"
                if e["type"] == "extra_forbidden":
                    msg = f"unknown key; expected one of: {', '.join(Step.model_fields)}"
                problems.append(f"{origin}: steps[{i}]{key}: {msg}{got}")
    if problems:
        raise UserError("\n".join(problems))
    return steps


def default_steps() -> list[Step]:
    """The embedded show (~24 s): every action once, idles between, a walk out and back."""
    table = [
        {"action": "idle", "duration": 1.5}, {"action": "wave"}, {"action": "idle", "duration": 0.8},
        {"action": "swipe_left"}, {"action": "swipe_right"}, {"action": "click"},
        {"action": "idle", "duration": 0.8}, {"action": "walk", "x_mm": 600.0}, {"action": "hand_raise"},
        {"action": "swipe_up"}, {"action": "swipe_down"}, {"action": "walk", "x_mm": 0.0},
        {"action": "idle", "duration": 1.0},
    ]
    return [Step.model_validate(s) for s in table]


@dataclass(frozen=True)
class Segment:
    """A step placed on the timeline (speed-1 seconds), with what it moves."""

    start: float
    length: float
    x: float  # where the performer stands when the step starts
    side: Side | None = None
    hand: HandMotion | None = None
    walk: Walk | None = None


class Timeline:
    """One pass through the steps: postures at any instant and the gesture intervals."""

    def __init__(self, steps: list[Step], body: Body, handedness: Side, start_x: float, z: float,
                 speed: float, offset: float = 0.0, origin: str = "choreography", sway_phase: float = 0.0) -> None:
        self.body, self.z, self.speed, self.offset, self.origin = body, z, speed, offset, origin
        self.sway_phase = sway_phase  # radians: people standing side by side do not sway in step
        self.segments: list[Segment] = []
        t, x = 0.0, start_x
        for i, step in enumerate(steps):
            segment = self._segment(i, step, t, x, handedness)
            self.segments.append(segment)
            t += segment.length
            x = segment.walk.x1 if segment.walk is not None else x
        self.end_x = x
        self.starts = [s.start for s in self.segments]
        self.length = t / speed  # seconds on the source clock
        self.gestures = tuple(
            TruthGesture(step.action, s.side, offset + (s.start + s.hand.gesture[0]) / speed,
                         offset + (s.start + s.hand.gesture[1]) / speed)
            for step, s in zip(steps, self.segments) if s.hand is not None and s.hand.gesture is not None)

    def _segment(self, i: int, step: Step, t: float, x: float, handedness: Side) -> Segment:
        if step.action == "idle":
            return Segment(t, step.duration or IDLE_S, x)
        if step.action == "walk":
            distance = step.x_mm - x
            length = step.duration or walk_length(distance)
            walk = Walk(x, step.x_mm, length)
            if abs(walk.cruise) > WALK_MAX_MM_S:
                needed = abs(distance) / WALK_MAX_MM_S + walk.ramp
                raise UserError(f"{self.origin}[{i}]: walking {abs(distance):.0f} mm (to x_mm = {step.x_mm:g}) in "
                                f"{length:g} s is running; give a duration of at least {needed:.1f} s or leave it out")
            return Segment(t, length, x, walk=walk)
        side = Side(step.hand) if step.hand else handedness
        motion = hand_motion(step.action, self.body, side, step.duration)
        return Segment(t, max(step.duration or 0.0, motion.length), x, side, motion)

    def posture(self, t: float) -> Posture:
        """The posture `t` seconds (source clock, this pass's offset included) into the show."""
        show = (t - self.offset) * self.speed
        i = max(bisect.bisect_right(self.starts, show) - 1, 0)
        seg = self.segments[i]
        local = show - seg.start
        hands = {side: self.body.rest(side) for side in SIDES}
        x, yaw, phase, gait = seg.x, 0.0, 0.0, 0.0
        if seg.walk is not None:
            walk = seg.walk
            x, yaw, phase, gait = walk.x(local), walk.yaw(local), walk.phase(local), walk.swing(local)
            hands = {side: walk.arm(self.body, side, local) for side in SIDES}
        elif seg.hand is not None:
            hands[seg.side] = seg.hand.at(local)
        sway = SWAY_MM * np.sin(2 * np.pi * SWAY_HZ * t + self.sway_phase)
        return Posture(x + sway, self.z, yaw, hands, phase, gait)

    def active(self, t: float) -> tuple[TruthGesture, ...]:
        return tuple(g for g in self.gestures if g.start <= t <= g.end)
