"""Scenes: several performers on one stage, each with its own body, place and choreography.

A performer starts at `x_mm` along the stage at depth `distance_mm` and plays its own steps on
the shared clock; all start together. One that starts beyond the edge of the picture and walks
in is entering; one that walks out is leaving (the stage is wider than the camera sees:
`offstage_x` says where the picture ends at a depth). The built-in scenes below are written so
that every performer ends where it began, so a looping scene repeats seamlessly.
"""
from __future__ import annotations

import math
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from host.options import ProfilePath
from sources.fakenect import KINECT_V1_FOV_DEG
from sources.synthetic.choreography import Step, load_file

SceneName = Literal["duet", "handover", "trio", "range", "quartet"]
OFFSTAGE_MARGIN_MM = 700.0  # beyond the picture's edge by this much, not even a hand shows


def offstage_x(distance_mm: float) -> float:
    """Stage x (mm) just out of the camera's view, to the image's right, at this depth."""
    return distance_mm * math.tan(math.radians(KINECT_V1_FOV_DEG[0] / 2)) + OFFSTAGE_MARGIN_MM


class PerformerOptions(BaseModel):
    """One performer of a scene (the `performers` list of the synthetic source)."""

    model_config = ConfigDict(extra="forbid")
    height_mm: float = Field(1750.0, ge=1000, le=2300, description="standing height (a child: 1000-1400)")
    distance_mm: float = Field(2500.0, ge=800, le=6000, description="distance from the camera")
    x_mm: float = Field(0.0, ge=-6000, le=6000, description="where the performer starts, mm towards the image's right")
    handedness: Literal["right", "left"] = Field("right", description="hand for steps that name none")
    choreography: list[Step] | None = Field(None, min_length=1, description="steps, inline")
    choreography_file: ProfilePath | None = Field(None, description="TOML file with a `steps` list")

    @model_validator(mode="after")
    def _one_choreography(self) -> "PerformerOptions":
        if (self.choreography is None) == (self.choreography_file is None):
            raise ValueError("give each performer a choreography or a choreography_file (one of them)")
        return self

    def steps(self, where: str) -> tuple[list[Step], str]:
        """The steps and where they come from for messages (`where`: this performer's options)."""
        if self.choreography_file is not None:
            return load_file(self.choreography_file), f"{self.choreography_file}: steps"
        return list(self.choreography or ()), f"{where}.choreography"


def _walk(x: float, seconds: float) -> dict:
    return {"action": "walk", "x_mm": round(x), "duration": seconds}


def _idle(seconds: float) -> dict:
    return {"action": "idle", "duration": seconds}


def _duet() -> list[dict]:
    """Two performers cross twice, the near one (2.0 m) passing in front of the far one (3.2 m)
    at the picture's centre each time (their walks are timed to meet there), with a gesture each
    between the crossings."""
    return [
        {"height_mm": 1750, "distance_mm": 2000, "x_mm": -750, "choreography": [
            _idle(1.0), {"action": "wave", "hand": "right", "duration": 2.4}, _walk(750, 2.5), _idle(0.5),
            {"action": "swipe_left", "hand": "right"}, _walk(-750, 2.5), _idle(1.0)]},
        {"height_mm": 1650, "distance_mm": 3200, "x_mm": 1100, "handedness": "left", "choreography": [
            _idle(1.0), {"action": "click", "duration": 2.4}, _walk(-1100, 2.5), _idle(0.5),
            {"action": "swipe_up", "duration": 1.85}, _walk(1100, 2.5), _idle(1.0)]},
    ]


def _handover() -> list[dict]:
    """One performer leaves to the right while another enters from the left; later the first
    comes back from where it left while the second leaves the way it came."""
    out_right, out_left = offstage_x(2500), -offstage_x(3000)
    return [
        {"height_mm": 1750, "distance_mm": 2500, "x_mm": -300, "choreography": [
            _idle(1.0), {"action": "wave", "duration": 2.4}, _walk(out_right, 3.0), _idle(1.8),
            _walk(-300, 3.0), {"action": "swipe_right"}, _idle(1.0)]},
        {"height_mm": 1600, "distance_mm": 3000, "x_mm": out_left, "choreography": [
            _idle(3.4), _walk(300, 3.0), {"action": "click", "hand": "left", "duration": 1.8},
            _walk(out_left, 3.0), _idle(2.85)]},
    ]


def _trio() -> list[dict]:
    """A child near the camera (1.5 m) waves and walks across in front of two adults (2.6 m and
    4.2 m), hiding the far one for a while; everyone gestures; the child walks back at the end."""
    return [
        {"height_mm": 1150, "distance_mm": 1500, "x_mm": -600, "choreography": [
            _idle(0.5), {"action": "wave", "duration": 2.4}, _walk(200, 2.5), {"action": "hand_raise"},
            _walk(-600, 2.5), _idle(1.0)]},
        {"height_mm": 1800, "distance_mm": 2600, "x_mm": 750, "choreography": [
            _idle(1.0), {"action": "swipe_left"}, _idle(1.5), {"action": "click"}, _idle(1.0),
            {"action": "swipe_down", "hand": "left"}, _idle(3.5)]},
        {"height_mm": 1650, "distance_mm": 4200, "x_mm": -200, "handedness": "left", "choreography": [
            _idle(2.0), {"action": "hand_raise"}, _walk(-1300, 2.0), {"action": "swipe_up"},
            _walk(-200, 2.0), _idle(1.9)]},
    ]


def _range() -> list[dict]:
    """The ends of the range people are tracked in: a child 0.9 m from the camera (its legs below
    the picture) gestures while an adult 4.4 m away walks behind it and back."""
    return [
        {"height_mm": 1200, "distance_mm": 900, "x_mm": -150, "choreography": [
            _idle(1.0), {"action": "wave"}, _idle(1.0), {"action": "swipe_right"}, _idle(1.0),
            {"action": "click", "hand": "left"}, _idle(2.0)]},
        {"height_mm": 1800, "distance_mm": 4400, "x_mm": 1400, "choreography": [
            {"action": "hand_raise", "hand": "left"}, _walk(-1400, 3.0), {"action": "swipe_left"},
            _walk(1400, 3.0), _idle(1.0)]},
    ]


def _quartet() -> list[dict]:
    """Four people, as many as the engine tracks: an adult walks in front of a far one and back,
    a child gestures beside them, two others gesture where they stand."""
    return [
        {"height_mm": 1750, "distance_mm": 2200, "x_mm": -500, "choreography": [
            _idle(0.5), {"action": "wave", "duration": 2.4}, _walk(300, 2.5), {"action": "swipe_left"},
            _walk(-500, 2.5), _idle(1.0)]},
        {"height_mm": 1100, "distance_mm": 1800, "x_mm": 600, "choreography": [
            _idle(1.0), {"action": "click"}, _idle(2.0), {"action": "hand_raise"}, _idle(3.0)]},
        {"height_mm": 1700, "distance_mm": 3400, "x_mm": 1500, "choreography": [
            _idle(2.0), {"action": "swipe_right"}, _idle(2.0), {"action": "swipe_down", "hand": "left"}, _idle(3.0)]},
        {"height_mm": 1850, "distance_mm": 4300, "x_mm": -2000, "choreography": [
            {"action": "hand_raise"}, _walk(-500, 2.0), {"action": "swipe_up"}, _walk(-2000, 2.0), _idle(2.2)]},
    ]


SCENES = {"duet": _duet, "handover": _handover, "trio": _trio, "range": _range, "quartet": _quartet}


def scene(name: SceneName) -> list[PerformerOptions]:
    """A built-in scene's performers."""
    return [PerformerOptions.model_validate(p) for p in SCENES[name]()]
