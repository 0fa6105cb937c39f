"""`synthetic`: procedural performers seen by a simulated Kinect v1, with ground truth.

The embedded default source: no camera needed. Each frame is rendered from the choreography at
the frame's timestamp (k / fps exactly), so the show is the same however fast it is read; the
host paces it in real time (it is not `live`). One performer by default; a `scene` (built in)
or a `performers` list puts several on the stage (scene.py), each with its truth in `Truth.users`.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, model_validator

from host import DepthFrame, Intrinsics, Side, Source, Truth, UserTruth
from host.options import ProfilePath
from sources.fakenect import KINECT_V1_FOV_DEG
from sources.synthetic.choreography import Step, Timeline, default_steps, load_file
from sources.synthetic.performer import Body, Performer, Pose
from sources.synthetic.render import Raster, separate
from sources.synthetic.scene import PerformerOptions, SceneName, scene
from sources.synthetic.sensor import KinectModel

CAMERA_HEIGHT_MM = 1100.0  # the sensor on a stand at chest height, looking level
WALL_BEHIND_MM = 1500.0  # back wall distance behind the (farthest) performer
SWAY_PHASE = 2.4  # radians between one performer's idle sway and the next one's
SOLO = ("distance_mm", "height_mm", "handedness", "choreography", "choreography_file")  # one performer's options


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
    scene: SceneName | None = Field(None, description="several performers, built in: duet, handover, trio, range, quartet")
    performers: list[PerformerOptions] | None = Field(
        None, min_length=1, max_length=6, description="several performers, each with its own place and steps")

    @model_validator(mode="after")
    def _one_choreography(self) -> "SyntheticOptions":
        if self.choreography is not None and self.choreography_file is not None:
            raise ValueError("give choreography or choreography_file, not both")
        if self.scene is not None and self.performers is not None:
            raise ValueError("give scene or performers, not both")
        solo = sorted(self.model_fields_set & set(SOLO))
        if (self.scene is not None or self.performers is not None) and solo:
            raise ValueError(f"{', '.join(solo)}: with a scene or performers, give these for each performer "
                             "(in `performers`), not for the source")
        return self

    def cast(self) -> list[PerformerOptions]:
        """Who is on stage: the scene's performers, or the one the source's own options describe."""
        if self.scene is not None:
            return scene(self.scene)
        if self.performers is not None:
            return list(self.performers)
        return [PerformerOptions(height_mm=self.height_mm, distance_mm=self.distance_mm, handedness=self.handedness,
                                 choreography=self.choreography or (None if self.choreography_file else default_steps()),
                                 choreography_file=self.choreography_file)]


@dataclass
class Actor:
    """One performer on stage: its scene id (1, 2, ... in the order given), body, steps and current pass."""

    id: int
    options: PerformerOptions
    steps: list[Step]
    origin: str
    body: Body
    timeline: Timeline | None = None
    performer: Performer | None = None

    def plan(self, start_x: float, offset: float, speed: float) -> None:
        """This performer's next pass through its steps, from `start_x`, starting `offset` s into the show."""
        o = self.options
        self.timeline = Timeline(self.steps, self.body, Side(o.handedness), start_x, o.distance_mm, speed, offset,
                                 self.origin, SWAY_PHASE * (self.id - 1))


class SyntheticSource(Source):
    """Performers of configurable height and handedness doing a scripted show, seen by a Kinect."""

    name = "synthetic"
    Options = SyntheticOptions

    def __init__(self, options: SyntheticOptions | None = None) -> None:
        super().__init__(options)
        o: SyntheticOptions = self.options
        self.actors = []
        for i, performer in enumerate(o.cast()):
            where = "source" if o.scene is None and o.performers is None else f"source.performers[{i}]"
            self.actors.append(Actor(i + 1, performer, *performer.steps(where), Body(performer.height_mm)))
        self.fps = float(o.fps)
        self.intrinsics = Intrinsics.from_fov(o.width, o.height, *KINECT_V1_FOV_DEG)
        self._restart()  # checks the walks now, not mid-show

    @property
    def steps(self) -> list[Step]:
        return self.actors[0].steps

    @property
    def body(self) -> Body:
        return self.actors[0].body

    @property
    def timeline(self) -> Timeline:
        """The first performer's current pass."""
        return self.actors[0].timeline

    def _restart(self) -> None:
        for actor in self.actors:
            actor.plan(actor.options.x_mm, 0.0, self.options.speed)
        self.offset, self.length = 0.0, max(a.timeline.length for a in self.actors)

    def open(self) -> None:
        o: SyntheticOptions = self.options
        rng = np.random.default_rng(o.seed)
        self.raster = Raster(o.width, o.height, self.intrinsics)
        farthest = max(a.options.distance_mm for a in self.actors)
        wall = farthest + WALL_BEHIND_MM if o.background == "room" else None
        self.room = self.raster.room(-CAMERA_HEIGHT_MM, wall)
        self.zbuf = np.empty_like(self.room)  # reused: the frame's data is a fresh array anyway
        self.scratch = np.full_like(self.room, np.inf)
        self.sensor = KinectModel(o.width, o.height, self.intrinsics.fx, o.mirrored, o.noise, o.holes, rng)
        for actor in self.actors:
            actor.performer = Performer(actor.body, o.mirrored, -CAMERA_HEIGHT_MM)
        self._restart()
        self.frame_id = 0

    def read(self) -> DepthFrame | None:
        t = self.frame_id / self.fps
        end = self.offset + self.length
        if t >= end:
            if not self.options.loop:
                return None
            for actor in self.actors:  # each next pass starts where the last one ended
                actor.plan(actor.timeline.end_x, end, self.options.speed)
            self.offset, self.length = end, max(a.timeline.length for a in self.actors)
        np.copyto(self.zbuf, self.room)
        labels = np.zeros(self.zbuf.shape, np.uint8)
        regions, everyone = [], []
        for actor in self.actors:
            pose = actor.performer.pose(actor.timeline.posture(t))
            regions.append(self.raster.draw_labelled(self.zbuf, pose.shapes, self.scratch, labels, actor.id))
            everyone.append((UserTruth(actor.id, pose.hands, pose.body, actor.timeline.active(t)), self._in_view(pose)))
        data = self.sensor.capture(self.zbuf, separate(regions))
        data.flags.writeable = False
        labels.flags.writeable = False
        truth = self._truth(everyone, labels)
        frame = DepthFrame(data, self.intrinsics, frame_id=self.frame_id, timestamp=t,
                           mirrored=self.options.mirrored, truth=truth)
        self.frame_id += 1
        return frame

    def _in_view(self, pose: Pose) -> bool:
        """A performer is in view while its torso is inside the picture (partly hidden by another or not)."""
        u, _, _ = self.intrinsics.world_to_depth(*pose.joints["torso"])
        return 0 <= u < self.options.width

    def _truth(self, everyone: list[tuple[UserTruth, bool]], labels: np.ndarray) -> Truth:
        """Every performer in view in `users`; the first of them gives hands, body and gestures (a
        lone performer always does, in view or not, as before scenes existed)."""
        users = tuple(user for user, seen in everyone if seen)
        first = users[0] if users else everyone[0][0] if len(everyone) == 1 else None
        if first is None:
            return Truth(user_labels=labels)
        return Truth(hands=first.hands, gestures=first.gestures, body=first.body, users=users, user_labels=labels)
