"""The data model every part of issv speaks (docs/architecture.md, thesis Fig. 32-33).

Positions are millimetres in camera coordinates: x right (towards the image's right), y up,
z away from the camera. Times are seconds. Frames and events are immutable so that the sensor
thread can hand them to the show loop without copies or locks.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from enum import Enum
from functools import cached_property
from typing import Callable, Mapping

import numpy as np

Vec3 = tuple[float, float, float]


class HandState(str, Enum):
    """OIHandState."""

    NEW = "new"
    TRACKING = "tracking"
    LOST = "lost"
    TOUCHING_FOV = "touching_fov"
    ABSENT = "absent"


class GestureState(str, Enum):
    """OIGestureState (ABSENT is never emitted: no event means no gesture)."""

    IN_PROGRESS = "in_progress"
    COMPLETE = "complete"


class GestureType(str, Enum):
    """OIGestureType: NiTE2's dictionary (WAVE, CLICK, HAND_RAISE) and Nuitrack's."""

    WAVE = "WAVE"
    CLICK = "CLICK"
    HAND_RAISE = "HAND_RAISE"
    WAVING = "WAVING"
    PUSH = "PUSH"
    SWIPE_LEFT = "SWIPE_LEFT"
    SWIPE_RIGHT = "SWIPE_RIGHT"
    SWIPE_UP = "SWIPE_UP"
    SWIPE_DOWN = "SWIPE_DOWN"
    LEARNED = "learned"  # taught by example (host/learned): its name is the Gesture's `label`

    @property
    def canonical(self) -> str:
        """The middleware-independent name (`wave` for WAVE and WAVING, `click` for CLICK and PUSH)."""
        return _CANONICAL.get(self, self.value)

    @classmethod
    def from_canonical(cls, name: str) -> "GestureType":
        """The first dictionary entry with this canonical name (WAVE for `wave`, CLICK for `click`)."""
        for member in cls:
            if member.canonical == name and member is not cls.LEARNED:
                return member
        raise ValueError(f"unknown gesture {name!r}; expected one of {', '.join(CANONICAL_GESTURES)}")


_CANONICAL = {
    GestureType.WAVE: "wave",
    GestureType.WAVING: "wave",
    GestureType.CLICK: "click",
    GestureType.PUSH: "click",
    GestureType.HAND_RAISE: "hand_raise",
    GestureType.SWIPE_LEFT: "swipe_left",
    GestureType.SWIPE_RIGHT: "swipe_right",
    GestureType.SWIPE_UP: "swipe_up",
    GestureType.SWIPE_DOWN: "swipe_down",
}
CANONICAL_GESTURES: tuple[str, ...] = (
    "wave", "click", "hand_raise", "swipe_left", "swipe_right", "swipe_up", "swipe_down",
)


class Side(str, Enum):
    """Which hand, from the performer's point of view."""

    LEFT = "left"
    RIGHT = "right"
    UNKNOWN = "unknown"


@dataclass(frozen=True)
class Intrinsics:
    """Pinhole intrinsics in pixels: world mm <-> depth pixels (convertHandCoordinatesToDepth)."""

    fx: float
    fy: float
    cx: float
    cy: float

    @classmethod
    def from_fov(cls, width: int, height: int, hfov_deg: float, vfov_deg: float) -> "Intrinsics":
        """Intrinsics of a sensor with this resolution and field of view (Kinect v1: 57 x 43 degrees)."""
        fx = (width / 2) / np.tan(np.radians(hfov_deg) / 2)
        fy = (height / 2) / np.tan(np.radians(vfov_deg) / 2)
        return cls(float(fx), float(fy), width / 2, height / 2)

    def world_to_depth(self, x: float, y: float, z: float) -> tuple[float, float, float]:
        """(x, y, z) mm -> (u, v, z): pixel column, pixel row, depth in mm."""
        return (x * self.fx / z + self.cx, self.cy - y * self.fy / z, z)

    def depth_to_world(self, u: float, v: float, z: float) -> Vec3:
        """(u, v, z) pixel column, row and depth in mm -> (x, y, z) mm."""
        return ((u - self.cx) * z / self.fx, (self.cy - v) * z / self.fy, z)

    def scaled(self, sx: float, sy: float) -> "Intrinsics":
        """The same camera seen at another resolution (sx, sy: new size / old size)."""
        return Intrinsics(self.fx * sx, self.fy * sy, self.cx * sx, self.cy * sy)

    def as_list(self) -> list[float]:
        return [self.fx, self.fy, self.cx, self.cy]


@dataclass(frozen=True)
class TruthGesture:
    """A gesture the performer really did, with its interval in source seconds."""

    name: str
    side: Side
    start: float
    end: float


@dataclass(frozen=True)
class UserTruth:
    """One performer of several: who they are in the scene (`id`, the source's own numbering,
    stable for the whole scene) and their hands, body points and gestures at this instant."""

    id: int
    hands: dict[Side, Vec3] = field(default_factory=dict)
    body: dict[str, Vec3] = field(default_factory=dict)
    gestures: tuple[TruthGesture, ...] = ()


@dataclass(frozen=True)
class Truth:
    """Ground truth a source knows (synthetic performer, clips with skeletons).

    `hands`, `gestures` and `body` are the first performer's (the only one for most sources);
    a scene of several performers also lists every performer in view in `users`.
    `user_labels` (optional): uint8 (H, W) at the depth image's size, which performer's body is
    nearest at each pixel (0 = nobody, else a `users` id), also where the sensor read nothing:
    what a segmentation should find.
    """

    hands: dict[Side, Vec3] = field(default_factory=dict)
    gestures: tuple[TruthGesture, ...] = ()
    body: dict[str, Vec3] = field(default_factory=dict)
    users: tuple[UserTruth, ...] = ()
    user_labels: np.ndarray | None = field(default=None, compare=False, repr=False)


def _owned(array: np.ndarray) -> np.ndarray:
    """The array itself if it is a read-only, contiguous array of its own, else such a copy: a
    frame's pixels can then cross threads without locks."""
    if array.flags.writeable or array.base is not None or not array.flags.c_contiguous:
        array = np.ascontiguousarray(array).copy()
        array.flags.writeable = False
    return array


@dataclass(frozen=True, eq=False)
class DepthFrame:
    """One depth image: uint16 millimetres, 0 = no reading. Owns a read-only copy of its array.

    `timestamp` is the source's clock (seconds into a clip); `capture_time` is the host's wall
    clock (time.time()) when the frame was captured, so latency can be measured across processes.
    """

    data: np.ndarray
    intrinsics: Intrinsics
    frame_id: int = 0
    timestamp: float = 0.0
    capture_time: float = field(default_factory=time.time)
    mirrored: bool = True
    truth: Truth | None = None

    def __post_init__(self) -> None:
        data = self.data
        if data.dtype != np.uint16 or data.ndim != 2:
            raise ValueError(f"DepthFrame.data must be a 2-D uint16 array, got {data.dtype} {data.shape}")
        object.__setattr__(self, "data", _owned(data))

    @property
    def width(self) -> int:
        return int(self.data.shape[1])

    @property
    def height(self) -> int:
        return int(self.data.shape[0])

    def world_to_depth(self, position: Vec3) -> tuple[float, float, float]:
        return self.intrinsics.world_to_depth(*position)

    def depth_to_world(self, u: float, v: float, z: float) -> Vec3:
        return self.intrinsics.depth_to_world(u, v, z)


@dataclass(frozen=True, eq=False)
class ColourFrame:
    """One colour image from an RGB camera or a video: uint8 (H, W, 3), RGB order. Owns a
    read-only copy of its array. `intrinsics` come from the camera's field of view; `mirrored`
    says whether the image is flipped as a mirror (a selfie view). Times as DepthFrame's."""

    rgb: np.ndarray
    intrinsics: Intrinsics
    frame_id: int = 0
    timestamp: float = 0.0
    capture_time: float = field(default_factory=time.time)
    mirrored: bool = False

    def __post_init__(self) -> None:
        rgb = self.rgb
        if rgb.dtype != np.uint8 or rgb.ndim != 3 or rgb.shape[2] != 3:
            raise ValueError(f"ColourFrame.rgb must be a (H, W, 3) uint8 array, got {rgb.dtype} {rgb.shape}")
        object.__setattr__(self, "rgb", _owned(rgb))

    @property
    def width(self) -> int:
        return int(self.rgb.shape[1])

    @property
    def height(self) -> int:
        return int(self.rgb.shape[0])


def _plain_numbers(event: "Hand | Gesture") -> None:
    """Backends may compute with numpy; events carry plain Python numbers so every consumer
    (JSON lines, OSC, recordings, the network) can serialise them."""
    object.__setattr__(event, "position", tuple(float(c) for c in event.position))
    object.__setattr__(event, "confidence", float(event.confidence))


@dataclass(frozen=True)
class Hand:
    """OIHandData: one tracked hand."""

    id: int
    state: HandState
    position: Vec3
    side: Side = Side.UNKNOWN
    user_id: int = 1
    confidence: float = 1.0
    #: whether the hand sticks out of the body (None: the backend does not say). Backends that
    #: report users report both hands all the time, resting ones with extended = False.
    extended: bool | None = None

    def __post_init__(self) -> None:
        _plain_numbers(self)

    @property
    def in_view(self) -> bool:
        """NEW, TRACKING or TOUCHING_FOV: where it is now. A LOST or ABSENT hand is gone (its
        position is where it was last seen)."""
        return self.state not in (HandState.LOST, HandState.ABSENT)

    def to_json(self) -> dict:
        return {"id": self.id, "state": self.state.value, "side": self.side.value,
                "position": [round(c, 1) for c in self.position]}


@dataclass(frozen=True)
class Gesture:
    """OIGestureData: one gesture event. `timestamp` is source seconds."""

    type: GestureType
    state: GestureState
    position: Vec3
    hand_id: int = 0
    side: Side = Side.UNKNOWN
    confidence: float = 1.0
    timestamp: float = 0.0
    user_id: int = 1
    label: str = ""  # a learned gesture's name (type LEARNED); empty for the built-in dictionary
    hands: tuple[int, ...] = ()  # a learned gesture made with both hands: their ids

    def __post_init__(self) -> None:
        _plain_numbers(self)
        object.__setattr__(self, "hands", tuple(int(h) for h in self.hands))

    @property
    def name(self) -> str:
        """Canonical name: an effect that listens for `wave` works on every backend. A learned
        gesture is called what it was taught as."""
        return self.label if self.type is GestureType.LEARNED and self.label else self.type.canonical

    def to_json(self) -> dict:
        extra = {"hands": list(self.hands)} if self.hands else {}
        return {"t": round(self.timestamp, 4), "type": "gesture", "name": self.name,
                "native": self.type.value, "state": self.state.value, "hand": self.hand_id,
                "side": self.side.value, "position": [round(c, 1) for c in self.position],
                "confidence": round(self.confidence, 3), **extra}


#: The joints a user's body may have, named from the performer's point of view (OSCeleton's
#: fifteen, spelled out). A backend reports those it has; `torso` and `head` feed the recogniser.
JOINTS: tuple[str, ...] = (
    "head", "neck", "torso",
    "left_shoulder", "left_elbow", "left_hand", "right_shoulder", "right_elbow", "right_hand",
    "left_hip", "left_knee", "left_foot", "right_hip", "right_knee", "right_foot",
)


@dataclass(frozen=True)
class Joint:
    """One body joint: millimetres (camera coordinates) and how sure the tracker is, 0..1."""

    position: Vec3
    confidence: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "position", tuple(float(c) for c in self.position))
        object.__setattr__(self, "confidence", float(self.confidence))


@dataclass(frozen=True)
class User:
    """One tracked person (NiTE's and Nuitrack's user, an OSC bridge's skeleton).

    `id` is stable while the person is tracked; `state` follows the hands' lifecycle: NEW on the
    first frame, TRACKING, then LOST once (after the backend's timeout) with the last body.
    `joints` maps names of JOINTS to Joint; `center_of_mass` is None when the backend has no
    estimate (the mean of the torso and hips is a fair one for a skeleton).
    """

    id: int
    state: HandState
    joints: Mapping[str, Joint] = field(default_factory=dict)
    center_of_mass: Vec3 | None = None

    @property
    def in_view(self) -> bool:
        return self.state not in (HandState.LOST, HandState.ABSENT)

    def to_json(self) -> dict:
        return {"id": self.id, "state": self.state.value,
                "center_of_mass": None if self.center_of_mass is None else list(self.center_of_mass),
                "joints": {name: {"position": list(j.position), "confidence": j.confidence}
                           for name, j in self.joints.items()}}

    @classmethod
    def from_json(cls, doc: dict) -> "User":
        com = doc.get("center_of_mass")
        return cls(int(doc["id"]), HandState(doc["state"]),
                   {str(name): Joint(tuple(j["position"]), float(j.get("confidence", 1.0)))
                    for name, j in doc.get("joints", {}).items()},
                   None if com is None else tuple(float(c) for c in com))


@dataclass(frozen=True)
class Frame:
    """One sensor instant as a backend reports it.

    `users` are the people the backend tracks (empty for backends that know only hands);
    `time` is the source's clock in seconds for frames without a depth image (an OSC tracker).
    `user_labels` is one label image for all users (uint8 (H, W) like depth: 0 nobody, else the
    user's id); `user_mask` is every user's pixels. Both are made on first use, off the sensor
    thread, so a show without a silhouette never pays for them.
    """

    seq: int
    capture_time: float
    depth: DepthFrame | None
    hands: tuple[Hand, ...] = ()
    gestures: tuple[Gesture, ...] = ()
    backend: str = ""
    make_user_mask: Callable[[], np.ndarray | None] | None = field(default=None, repr=False, compare=False)
    users: tuple[User, ...] = ()
    time: float = 0.0
    make_user_labels: Callable[[], np.ndarray | None] | None = field(default=None, repr=False, compare=False)

    @cached_property
    def user_labels(self) -> np.ndarray | None:
        """uint8 (H, W) like depth: 0 where nobody is, else the id of the user seen there."""
        return None if self.make_user_labels is None else self.make_user_labels()

    @cached_property
    def user_mask(self) -> np.ndarray | None:
        """bool (H, W) like depth: the performers' pixels, if the backend knows them."""
        if self.make_user_mask is not None:
            return self.make_user_mask()
        labels = self.user_labels
        return None if labels is None else labels > 0

    @property
    def timestamp(self) -> float:
        return self.depth.timestamp if self.depth is not None else self.time

    def hands_json(self) -> dict:
        """The `hands` event line of `issv track`."""
        return {"t": round(self.timestamp, 4), "type": "hands", "hands": [h.to_json() for h in self.hands]}
