"""`synthetic`: a procedural performer seen by a simulated Kinect v1, with ground truth.

The embedded default source: no camera needed. Each frame is rendered from the choreography at
the frame's timestamp (k / fps exactly), so the show is the same however fast it is read; the
host paces it in real time (it is not `live`).
"""
from __future__ import annotations

from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, model_validator

from host import DepthFrame, Intrinsics, Side, Source, Truth
from host.options import ProfilePath
from sources.fakenect import KINECT_V1_FOV_DEG
from sources.synthetic.choreography import Step, Timeline, default_steps, load_file
from sources.synthetic.performer import Body, Performer
from sources.synthetic.render import Raster
from sources.synthetic.sensor import KinectModel

CAMERA_HEIGHT_MM = 1100.0  # the sensor on a stand at chest height, looking level
WALL_BEHIND_MM = 1500.0  # back wall distance behind the performer


class SyntheticOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    distance_mm: float = Field(2500.0, ge=800, le=6000, description="performer's distance from the camera")
    height_mm: float = Field(1750.0, ge=1000, le=2300, description="performer's standing height")
    handedness: Literal["right", "left"] = Field("right", description="hand for steps that name none")
    speed: float = Field(1.0, ge=0.25, le=4.0, description="time multiplier for the whole choreography")
    fps: float = Field(30.0, ge=10, le=120)
    width: int = Field(640, ge=80, le=1280)
    height: int = Field(480, ge=60, le=960)
    noise: float = Field(1.0, ge=0, le=5, description="depth noise scale: 1 = Kinect v1, 0 = clean")
    holes: float = Field(1.0, ge=0, le=5, description="missing-reading scale: 1 = Kinect v1, 0 = none")
    background: Literal["room", "none"] = Field("room", description="floor and back wall, or nothing")
    seed: int | None = Field(None, description="noise seed; the same seed gives the same frames")
    mirrored: bool = Field(True, description="the performer's right hand on the image's right")
    loop: bool = False
    choreography: list[Step] | None = Field(None, min_length=1, description="steps, inline")
    choreography_file: ProfilePath | None = Field(None, description="TOML file with a `steps` list")

    @model_validator(mode="after")
    def _one_choreography(self) -> "SyntheticOptions":
        if self.choreography is not None and self.choreography_file is not None:
            raise ValueError("give choreography or choreography_file, not both")
        return self


class SyntheticSource(Source):
    """A performer of configurable height and handedness doing a scripted show, seen by a Kinect."""

    name = "synthetic"
    Options = SyntheticOptions

    def __init__(self, options: SyntheticOptions | None = None) -> None:
        super().__init__(options)
        o: SyntheticOptions = self.options
        if o.choreography_file is not None:
            self.steps, self.origin = load_file(o.choreography_file), f"{o.choreography_file}: steps"
        else:
            self.steps, self.origin = o.choreography or default_steps(), "source.choreography"
        self.fps = float(o.fps)
        self.intrinsics = Intrinsics.from_fov(o.width, o.height, *KINECT_V1_FOV_DEG)
        self.body = Body(o.height_mm)
        self.timeline = self._pass(0.0, 0.0)  # checks the walks now, not mid-show

    def _pass(self, start_x: float, offset: float) -> Timeline:
        o: SyntheticOptions = self.options
        return Timeline(self.steps, self.body, Side(o.handedness), start_x, o.distance_mm, o.speed, offset, self.origin)

    def open(self) -> None:
        o: SyntheticOptions = self.options
        rng = np.random.default_rng(o.seed)
        self.raster = Raster(o.width, o.height, self.intrinsics)
        wall = o.distance_mm + WALL_BEHIND_MM if o.background == "room" else None
        self.room = self.raster.room(-CAMERA_HEIGHT_MM, wall)
        self.zbuf = np.empty_like(self.room)  # reused: the frame's data is a fresh array anyway
        self.sensor = KinectModel(o.width, o.height, self.intrinsics.fx, o.mirrored, o.noise, o.holes, rng)
        self.performer = Performer(self.body, o.mirrored, -CAMERA_HEIGHT_MM)
        self.timeline = self._pass(0.0, 0.0)
        self.frame_id = 0

    def read(self) -> DepthFrame | None:
        t = self.frame_id / self.fps
        end = self.timeline.offset + self.timeline.length
        if t >= end:
            if not self.options.loop:
                return None
            self.timeline = self._pass(self.timeline.end_x, end)  # the next pass starts where this one ended
        pose = self.performer.pose(self.timeline.posture(t))
        np.copyto(self.zbuf, self.room)
        region = self.raster.draw(self.zbuf, pose.shapes)
        data = self.sensor.capture(self.zbuf, region)
        data.flags.writeable = False
        truth = Truth(hands=pose.hands, gestures=self.timeline.active(t), body=pose.body)
        frame = DepthFrame(data, self.intrinsics, frame_id=self.frame_id, timestamp=t,
                           mirrored=self.options.mirrored, truth=truth)
        self.frame_id += 1
        return frame
