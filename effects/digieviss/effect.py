"""`digieviss`: the forensic evidence application of the thesis (scenario I) as an effect.

Spheres o0..oN carry observations; the performer grabs them with a gesture, carries them and
links them into observation sequences; every change of the links rewrites a Forensic Lucid
program (Listing 5.1) so the investigator always has the current one on disk. Each user's left
and right hand can hold a sphere; a hand that comes down to rest keeps it (and links nothing
until it is raised again), so a backend that reports resting hands, such as `openiss`, plays it.
"""
from __future__ import annotations

import math
import os
import sys
from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from host import CANONICAL_GESTURES, Effect, Frame, Gesture, GestureState, Side, Stage, Vec3
from host.options import ProfilePath

from effects.digieviss import lucid
from effects.digieviss.scene import HandKey, Scene, Sphere


def hand_key(user_id: int, side: Side, hand_id: int) -> HandKey:
    """Who holds a sphere: the user's left or right hand, which stays that hand when it rests and
    comes up again whatever id a backend gives it; by id only when the backend cannot tell sides."""
    return HandKey(user_id, f"hand {hand_id}" if side is Side.UNKNOWN else side.value)


class SphereSpec(BaseModel):
    """One observation (property `evidence => value`, min, max, w, t) and where its sphere is."""

    model_config = ConfigDict(extra="forbid")
    evidence: str = Field(description='what was observed, e.g. "A printed"')
    value: str = Field(description='its value, e.g. "very well"')
    min: int = 1
    max: int = 0
    w: float = Field(1.0, ge=0, le=1, description="the observation's weight (credibility)")
    t: int = Field(0, description="its timestamp")
    position: tuple[float, float, float] | None = Field(None, description="camera mm (default: its place in the row)")
    radius: float | None = Field(None, gt=0, description="mm (default: radius_mm)")


LISTING_5_1 = [  # the four observations of the thesis' Listing 5.1
    SphereSpec(evidence="A printed", value="very well", w=0.85, t=1234),
    SphereSpec(evidence="B printed", value="well", w=0.65, t=2341),
    SphereSpec(evidence="C printed", value="not very well", w=0.35, t=3412),
    SphereSpec(evidence="D printed", value="not well", w=0.15, t=4123),
]


class DigiEVISSOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    spheres: list[SphereSpec] = Field(default_factory=lambda: list(LISTING_5_1), min_length=1,
                                      description="the observations, o0 first (default: the four of Listing 5.1)")
    observations: ProfilePath | None = Field(None, description="or preload them from a Forensic Lucid file's "
                                             "`observation oN = (...);` lines")
    program: ProfilePath = Field("digieviss.ipl", description="where the generated program is written "
                                 "(default: the working directory)")
    notation: Literal["list", "fby"] = Field("list", description="observation sequences as {o0, o1} or o0 fby o1")
    radius_mm: float = Field(120.0, gt=0, description="sphere radius unless a sphere sets its own")
    row_center: tuple[float, float, float] = Field(
        (0.0, 200.0, 2300.0), description="camera mm: the middle of the row of spheres that set no position "
        "(default: a raised hand of a performer 2.5 m from a camera at 1.1 m)")
    spacing_mm: float = Field(600.0, gt=0, description="between neighbouring centres in the row")
    planar: bool = Field(True, description="measure distances on the screen plane (x, y): the investigator "
                         "cannot see a virtual sphere's depth")
    grab_gesture: str = Field("click", description="grabs the sphere the hand is within")
    release_gesture: str = Field("click", description="lets go of the sphere the hand holds")
    lost_release_s: float = Field(0.5, gt=0, description="a held sphere is let go when its hand is unseen this long")
    hold_timeout_s: float = Field(10.0, ge=0, description="a held sphere is let go after this long (0: never)")
    touch_s: float = Field(0.1, ge=0, description="a carried sphere links to another once they touch this long "
                           "(a tracker's one-frame jump links none)")
    log: bool = Field(True, description="print grabs, releases, links and writes")

    @field_validator("grab_gesture", "release_gesture")
    @classmethod
    def _known(cls, name: str) -> str:
        if name not in CANONICAL_GESTURES:
            raise ValueError(f"expected one of {', '.join(CANONICAL_GESTURES)}")
        return name

    @model_validator(mode="after")
    def _one_source_of_observations(self) -> "DigiEVISSOptions":
        if self.observations is not None and "spheres" in self.model_fields_set:
            raise ValueError("set either `spheres` or `observations`, not both")
        return self


class DigiEVISS(Effect):
    name = "digieviss"
    Options = DigiEVISSOptions
    renders = True  # draws when the show has a renderer; the logic and the program need none

    def setup(self, stage: Stage) -> None:
        super().setup(stage)
        o = self.options
        self.observations, places = self._observations()
        self.scene = Scene([Sphere(ob.id, ob.data, pos, rad) for ob, (pos, rad) in zip(self.observations, places)],
                           o.planar, o.lost_release_s, o.hold_timeout_s, o.touch_s)
        self.written: str | None = None
        self.keys: dict[int, HandKey] = {}  # this frame's hand ids -> who they are
        self.view = None
        if stage.ctx is not None:
            from effects.digieviss.view import SceneView  # moderngl only when there is a renderer
            self.view = SceneView(stage)

    def _observations(self) -> tuple[list[lucid.Observation], list[tuple[Vec3, float]]]:
        o = self.options
        if o.observations is not None:
            found = lucid.read_observations(o.observations)
            chosen: list[tuple[Vec3 | None, float | None]] = [(None, None)] * len(found)
        else:
            found = [lucid.Observation(f"o{i}", lucid.observation_data(s.evidence, s.value, s.min, s.max, s.w, s.t))
                     for i, s in enumerate(o.spheres)]
            chosen = [(s.position, s.radius) for s in o.spheres]
        cx, cy, cz = o.row_center
        first = cx - o.spacing_mm * (len(found) - 1) / 2
        places = [(pos or (first + i * o.spacing_mm, cy, cz), rad or o.radius_mm)
                  for i, (pos, rad) in enumerate(chosen)]
        return found, places

    # -- input -------------------------------------------------------------------------------
    def on_frame(self, frame: Frame) -> None:
        in_view = [h for h in frame.hands if h.in_view]
        self.keys = {h.id: hand_key(h.user_id, h.side, h.id) for h in in_view}
        hands = {self.keys[h.id]: h.position for h in in_view}
        resting = {self.keys[h.id] for h in in_view if h.extended is False}
        changed = self.scene.update(hands, frame.timestamp, resting)
        self._flush_log()
        if changed:
            self.write_program()

    def on_gesture(self, gesture: Gesture) -> None:
        o = self.options
        grab, release = gesture.name == o.grab_gesture, gesture.name == o.release_gesture
        if gesture.state is not GestureState.COMPLETE or not (grab or release):
            return
        self.scene.grab_or_release(self._hand_of(gesture), gesture.position, gesture.timestamp, grab, release)
        self._flush_log()

    def _hand_of(self, gesture: Gesture) -> HandKey:
        """The gesture's hand: the tracked hand of its id, else by its user and side, else (a
        backend that cannot tell, id 0) the nearest tracked hand."""
        if gesture.hand_id in self.keys:
            return self.keys[gesture.hand_id]
        if gesture.side is not Side.UNKNOWN:
            return hand_key(gesture.user_id, gesture.side, gesture.hand_id)
        if gesture.hand_id or not self.scene.hands:
            return hand_key(gesture.user_id, Side.UNKNOWN, gesture.hand_id)
        return min(self.scene.hands, key=lambda h: math.dist(self.scene.hands[h], gesture.position))

    def _flush_log(self) -> None:
        if self.options.log:
            for line in self.scene.log:
                print(f"digieviss: {line.strip()}", flush=True)
        self.scene.log.clear()

    # -- output ------------------------------------------------------------------------------
    def program_text(self) -> str | None:
        """The current program, or None while no two spheres are linked."""
        if not self.scene.sequences:
            return None
        return lucid.program(self.observations, self.scene.sequences, self.options.notation)

    def write_program(self) -> None:
        """Replace the program file whole (write then rename), so a reader never sees half of one."""
        text = self.program_text()
        if text is None or text == self.written:
            return
        path = Path(self.options.program)
        tmp = path.with_name(path.name + ".tmp")
        try:
            tmp.write_text(text, encoding="utf-8")
            os.replace(tmp, path)
        except OSError as error:
            print(f"issv: digieviss cannot write the program to {path}: {error}", file=sys.stderr)
            return
        self.written = text
        if self.options.log:
            print(f"digieviss: wrote {path} ({len(self.scene.sequences)} observation sequence(s))", flush=True)

    def render(self, target) -> None:
        if self.view is not None:
            self.view.draw(self.scene, target)

    def close(self) -> None:
        if not hasattr(self, "scene"):
            return  # setup never finished
        self.write_program()
        if self.view is not None:
            self.view.release()
