"""What the skeleton bridges send, read back into users and joints in millimetres.

Each scheme turns one OSC message (address, arguments) into readings: a joint of a user at a
position in issv's camera millimetres (x towards the image's right, y up, z away), or a user
appearing or leaving. A message a scheme cannot read raises BadMessage with a short `kind`
(counted, and reported once per kind by the receiver); one it knows but has no use for (Synapse's
`_pos_screen`, KinectV2-OSC's hand states) returns nothing.

The schemes, as the bridges document their output:
- osceleton: `/new_user i`, `/new_skel i`, `/lost_user i`, `/joint s i f f f` in OSCeleton's
  normalised coordinates (x = (X + 1280) / 2560 towards the image's right, y = (960 - Y) / 1920,
  z = Z * 7.8125 / 10000; the same mapping the osc effect's preset sends). OpenNI's own X points
  the other way, which is why OSCeleton's source writes 1280 - X. `-mx/-my/-mz` and `-ox/-oy/-oz`
  are undone with the options `multiplier` and `offset`. Its `-k` (Animata: `/joint s f f`, the
  user id glued to the joint name, no z, no user messages) and `-q` (Quartz Composer:
  `/joint/<name>/<user> f f f`) variants are recognised by their shape.
- synapse: `/<joint>_pos_world f f f` in millimetres, one user; `/tracking_skeleton i`.
- ni-mate: the basic preset (`/<Joint_Name> f f f`, metres, one user) and its OSCeleton-style
  preset (`/joint s i f f f` with NI mate's joint names, metres).
- kinectv2: KinectV2-OSC's `/bodies/{id}/joints/{joint} f f f s` (metres, tracking state).
- mediapipe: a flat list of 33 pose world landmarks (x y z or x y z visibility each, metres,
  hip-centred, y down) at `/pose` or `/pose/<user>`, as MediaPipe-to-OSC bridges send them.
- custom: templates (`[[backend.messages]]`), with the osc effect's `{field}` placeholders.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any, Literal, Sequence

from pydantic import BaseModel, ConfigDict, model_validator

from host.osc import placeholders
from host import Vec3


MM_DECIMALS = 2


@dataclass(frozen=True)
class Reading:
    """A joint of a user (a bridge's own user id), in issv millimetres to the hundredth.

    No tracker measures finer than a tenth of a millimetre; below that are the wire's 32-bit
    float digits (OSCeleton's normalised floats come back a few 0.0001 mm off). Rounding gives a
    tracker's own decimals back exactly, so the recogniser sees the stream as sent."""

    user: int
    joint: str
    position: Vec3
    confidence: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "position", tuple(round(c, MM_DECIMALS) for c in self.position))


@dataclass(frozen=True)
class UserEvent:
    """A bridge says a user appeared (`new`) or left (`lost`)."""

    user: int
    kind: Literal["new", "lost"]


Event = Reading | UserEvent


class BadMessage(ValueError):
    """A message the scheme cannot read; `kind` groups alike ones for a report once per kind."""

    def __init__(self, kind: str, detail: str) -> None:
        super().__init__(f"{kind}: {detail}")
        self.kind = kind


def _floats(address: str, args: Sequence[Any], n: int) -> list[float]:
    values = list(args[:n])
    if len(values) < n or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
        raise BadMessage(f"{address} without {n} numbers", f"got {list(args)!r}")
    if not all(math.isfinite(v) for v in values):
        raise BadMessage(f"{address} with a non-finite number", f"got {list(args)!r}")
    return [float(v) for v in values]


def _user(address: str, value: Any) -> int:
    """A user id: an int, or a whole float (Pure Data has only floats)."""
    if isinstance(value, float) and value.is_integer():
        return int(value)
    if isinstance(value, bool) or not isinstance(value, int):
        raise BadMessage(f"{address} without an integer user id", f"got {value!r}")
    return value


def _sided(name: str) -> str:
    """OSCeleton's `l_hand` -> `left_hand`; other names as they are."""
    if name.startswith("l_"):
        return "left_" + name[2:]
    if name.startswith("r_"):
        return "right_" + name[2:]
    return name


class Scheme:
    """One bridge's messages. `mirrored`: whether +x is the performer's right in its positions."""

    mirrored = True

    def read(self, address: str, args: Sequence[Any]) -> list[Event]:
        raise NotImplementedError

    def keepalive(self) -> list[tuple[str, list]]:
        """Messages the bridge needs from us now and then to keep sending (Synapse)."""
        return []


class OSCeletonScheme(Scheme):
    """OSCeleton (Sensebloom) and its -k and -q variants; positions back in millimetres."""

    USER_MESSAGES = {"/new_user": "new", "/new_skel": "new", "/lost_user": "lost"}
    KITCHEN_NAME = re.compile(r"^([a-z_]+?)(\d+)$")

    def __init__(self, multiplier: Vec3 = (1.0, 1.0, 1.0), offset: Vec3 = (0.0, 0.0, 0.0),
                 kitchen_depth_mm: float = 2000.0) -> None:
        self.multiplier, self.offset = multiplier, offset
        self.kitchen_depth_mm = kitchen_depth_mm

    def to_mm(self, x: float, y: float, z: float | None) -> Vec3:
        (mx, my, mz), (ox, oy, oz) = self.multiplier, self.offset
        nx, ny = (x - ox) / mx, (y - oy) / my
        depth = self.kitchen_depth_mm if z is None else (z - oz) / mz * 1280.0
        return (nx * 2560.0 - 1280.0, 960.0 - ny * 1920.0, depth)

    def read(self, address: str, args: Sequence[Any]) -> list[Event]:
        kind = self.USER_MESSAGES.get(address)
        if kind is not None:
            if not args:
                raise BadMessage(f"{address} without a user id", "no arguments")
            return [UserEvent(_user(address, args[0]), kind)]
        if address == "/joint":
            if len(args) >= 5 and isinstance(args[0], str):  # the default: s i f f f
                x, y, z = _floats(address, args[2:], 3)
                return [Reading(_user(address, args[1]), _sided(args[0]), self.to_mm(x, y, z))]
            if len(args) >= 3 and isinstance(args[0], str):  # -k: s f f, "l_shoulder0"
                match = self.KITCHEN_NAME.match(args[0])
                if match is None:
                    raise BadMessage("/joint (kitchen mode) without a user number after the joint name",
                                     f"got {args[0]!r}")
                x, y = _floats(address, args[1:], 2)
                return [Reading(int(match.group(2)), _sided(match.group(1)), self.to_mm(x, y, None))]
            raise BadMessage("/joint without s i f f f (or s f f)", f"got {list(args)!r}")
        parts = address.split("/")
        if len(parts) == 4 and parts[1] == "joint" and parts[3].isdigit():  # -q: /joint/l_knee/3 f f f
            x, y, z = _floats(address, args, 3)
            return [Reading(int(parts[3]), _sided(parts[2]), self.to_mm(x, y, z))]
        raise BadMessage("unknown OSCeleton address", address)


SYNAPSE_JOINTS = {
    "head": "head", "torso": "torso", "lefthand": "left_hand", "righthand": "right_hand",
    "leftelbow": "left_elbow", "rightelbow": "right_elbow", "leftshoulder": "left_shoulder",
    "rightshoulder": "right_shoulder", "lefthip": "left_hip", "righthip": "right_hip",
    "leftknee": "left_knee", "rightknee": "right_knee", "leftfoot": "left_foot", "rightfoot": "right_foot",
}
SYNAPSE_WORLD = 2  # the argument of /<joint>_trackjointpos asking for world positions


class SynapseScheme(Scheme):
    """Synapse: one user, world positions in mm, kept coming by `/<joint>_trackjointpos 2`."""

    USER = 1

    def read(self, address: str, args: Sequence[Any]) -> list[Event]:
        name = address[1:]
        if name == "tracking_skeleton":
            value = _floats(address, args, 1)[0]
            return [UserEvent(self.USER, "new" if value else "lost")]
        for suffix in ("_pos_world", "_pos_body", "_pos_screen"):
            if name.endswith(suffix):
                joint = name[: -len(suffix)]
                if joint == "closesthand":
                    return []
                if joint not in SYNAPSE_JOINTS:
                    raise BadMessage("unknown Synapse joint", address)
                if suffix != "_pos_world":
                    return []  # we ask for world positions; the others are Synapse's own views
                return [Reading(self.USER, SYNAPSE_JOINTS[joint], tuple(_floats(address, args, 3)))]
        if name in SYNAPSE_JOINTS:  # gesture words (/righthand "up"): issv finds its own gestures
            return []
        raise BadMessage("unknown Synapse address", address)

    def keepalive(self) -> list[tuple[str, list]]:
        return [(f"/{joint}_trackjointpos", [SYNAPSE_WORLD]) for joint in SYNAPSE_JOINTS]


NIMATE_JOINTS = {j.replace("_", " ").title().replace(" ", "_"): j for j in (
    "head", "neck", "torso", "left_shoulder", "left_elbow", "left_hand", "right_shoulder", "right_elbow",
    "right_hand", "left_hip", "left_knee", "left_foot", "right_hip", "right_knee", "right_foot")}


class NiMateScheme(Scheme):
    """NI mate's skeleton tracker, basic (`/Left_Hand x y z`) or OSCeleton-style (`/joint s i f f f`):
    world space metres."""

    USER = 1

    def read(self, address: str, args: Sequence[Any]) -> list[Event]:
        if address == "/joint" and len(args) >= 5 and isinstance(args[0], str):
            joint = NIMATE_JOINTS.get(args[0]) or _sided(args[0].lower())
            return [Reading(_user(address, args[1]), joint, self._mm(_floats(address, args[2:], 3)))]
        joint = NIMATE_JOINTS.get(address[1:])
        if joint is None:
            raise BadMessage("unknown NI mate joint", address)
        return [Reading(self.USER, joint, self._mm(_floats(address, args, 3)))]

    @staticmethod
    def _mm(xyz: list[float]) -> Vec3:
        return (xyz[0] * 1000.0, xyz[1] * 1000.0, xyz[2] * 1000.0)


KINECT2_JOINTS = {
    "Head": "head", "Neck": "neck", "SpineMid": "torso", "SpineBase": "pelvis", "SpineShoulder": "shoulder_centre",
    "ShoulderLeft": "left_shoulder", "ElbowLeft": "left_elbow", "WristLeft": "left_wrist", "HandLeft": "left_hand",
    "ShoulderRight": "right_shoulder", "ElbowRight": "right_elbow", "WristRight": "right_wrist",
    "HandRight": "right_hand", "HipLeft": "left_hip", "KneeLeft": "left_knee", "AnkleLeft": "left_ankle",
    "FootLeft": "left_foot", "HipRight": "right_hip", "KneeRight": "right_knee", "AnkleRight": "right_ankle",
    "FootRight": "right_foot", "HandTipLeft": "left_hand_tip", "ThumbLeft": "left_thumb",
    "HandTipRight": "right_hand_tip", "ThumbRight": "right_thumb",
}
KINECT2_CONFIDENCE = {"Tracked": 1.0, "Inferred": 0.5, "NotTracked": 0.0}


class KinectV2Scheme(Scheme):
    """KinectV2-OSC: `/bodies/{id}/joints/{joint} x y z state`, metres, body ids as the SDK gives them
    (64-bit tracking ids, numbered 1, 2, ... here in order of appearance)."""

    def __init__(self) -> None:
        self._ids: dict[str, int] = {}

    def read(self, address: str, args: Sequence[Any]) -> list[Event]:
        parts = address.split("/")
        if len(parts) != 5 or parts[1] != "bodies" or parts[3] not in ("joints", "hands"):
            raise BadMessage("unknown KinectV2-OSC address", address)
        user = self._ids.setdefault(parts[2], len(self._ids) + 1)
        if parts[3] == "hands":
            return []  # Open / Closed: issv's hands have no grip state yet
        joint = KINECT2_JOINTS.get(parts[4])
        if joint is None:
            raise BadMessage("unknown KinectV2 joint", address)
        x, y, z = _floats(address, args, 3)
        state = args[3] if len(args) > 3 else "Tracked"
        confidence = KINECT2_CONFIDENCE.get(state, 1.0) if isinstance(state, str) else 1.0
        if confidence == 0.0:
            return []
        return [Reading(user, joint, (x * 1000.0, y * 1000.0, z * 1000.0), confidence)]


MEDIAPIPE_POSE = (  # the 33 pose landmarks, in MediaPipe's order, those issv names
    {0: "head", 11: "left_shoulder", 12: "right_shoulder", 13: "left_elbow", 14: "right_elbow",
     15: "left_wrist", 16: "right_wrist", 19: "left_hand", 20: "right_hand", 23: "left_hip", 24: "right_hip",
     25: "left_knee", 26: "right_knee", 27: "left_ankle", 28: "right_ankle", 31: "left_foot", 32: "right_foot"})


class MediaPipeScheme(Scheme):
    """MediaPipe pose world landmarks as one flat list: metres, origin between the hips, y down,
    x along the (unmirrored) image: +x is the performer's left, so `mirrored` is False. Placed
    `depth_mm` from the camera; the torso is the mean of shoulders and hips."""

    mirrored = False
    LANDMARKS = 33

    def __init__(self, address: str = "/pose", depth_mm: float = 2500.0) -> None:
        self.address, self.depth_mm = address, depth_mm

    def read(self, address: str, args: Sequence[Any]) -> list[Event]:
        user = 1
        if address != self.address:
            head, _, tail = address.rpartition("/")
            if head != self.address or not tail.isdigit():
                raise BadMessage("unknown MediaPipe address", f"{address} (expected {self.address} or "
                                 f"{self.address}/<user>)")
            user = int(tail) + 1  # bridges count people from 0
        if len(args) not in (self.LANDMARKS * 3, self.LANDMARKS * 4):
            raise BadMessage(f"{self.address} without 33 x 3 or 33 x 4 numbers", f"got {len(args)} values")
        step = len(args) // self.LANDMARKS
        values = _floats(address, args, len(args))
        readings = []
        for index, joint in MEDIAPIPE_POSE.items():
            x, y, z = values[index * step: index * step + 3]
            confidence = values[index * step + 3] if step == 4 else 1.0
            readings.append(Reading(user, joint, (x * 1000.0, -y * 1000.0, self.depth_mm + z * 1000.0), confidence))
        by_name = {r.joint: r.position for r in readings}
        trunk = [by_name[j] for j in ("left_shoulder", "right_shoulder", "left_hip", "right_hip")]
        readings.append(Reading(user, "torso", tuple(sum(c) / 4 for c in zip(*trunk))))
        return readings


InputField = Literal["user", "joint", "x", "y", "z", "confidence"]
INPUT_FIELDS: dict[str, tuple[str, ...]] = {
    "joint": ("user", "joint", "x", "y", "z", "confidence"),
    "new_user": ("user",), "lost_user": ("user",),
}


class InputTemplate(BaseModel):
    """One message the `custom` scheme reads: `address` with `{field}` placeholders (the osc effect's
    template syntax); `args` says which argument is which field ("{x}"), or a literal to skip.
    Positions are multiplied by the option `scale` to make millimetres."""

    model_config = ConfigDict(extra="forbid")
    on: Literal["joint", "new_user", "lost_user"] = "joint"
    address: str
    args: list[str] = []

    @model_validator(mode="after")
    def _check(self) -> "InputTemplate":
        known = INPUT_FIELDS[self.on]
        for name in [n for text in [self.address, *self.args] for n in placeholders(text)]:
            if name not in known:
                raise ValueError(f"unknown field {{{name}}} for on = {self.on!r}; expected one of {', '.join(known)}")
        if not self.address.startswith("/"):
            raise ValueError(f"address must start with /, got {self.address!r}")
        fields = set(placeholders(self.address)) | {a[1:-1] for a in self.args if re.fullmatch(r"\{\w+\}", a)}
        needed = {"joint": {"joint", "x", "y", "z"}, "new_user": set(), "lost_user": set()}[self.on]
        if needed - fields:
            raise ValueError(f"on = {self.on!r} needs {', '.join(sorted(needed - fields))} in the address or args")
        return self

    def pattern(self) -> re.Pattern:
        """The address as a regular expression: each {field} matches one address part."""
        out, pos = "", 0
        for match in re.finditer(r"\{(\w+)\}", self.address):
            out += re.escape(self.address[pos:match.start()]) + f"(?P<{match.group(1)}>[^/]+)"
            pos = match.end()
        return re.compile(f"^{out}{re.escape(self.address[pos:])}$")


class CustomScheme(Scheme):
    """The artist's own addresses, read through templates."""

    def __init__(self, templates: list[InputTemplate], scale: float = 1.0, default_user: int = 1,
                 mirrored: bool = True) -> None:
        self.templates = [(t, t.pattern()) for t in templates]
        self.scale, self.default_user, self.mirrored = scale, default_user, mirrored

    def read(self, address: str, args: Sequence[Any]) -> list[Event]:
        for template, pattern in self.templates:
            match = pattern.match(address)
            if match is None:
                continue
            fields: dict[str, Any] = dict(match.groupdict())
            for spec, value in zip(template.args, args):
                alone = re.fullmatch(r"\{(\w+)\}", spec)
                if alone:
                    fields[alone.group(1)] = value
            if len(args) < len(template.args):
                raise BadMessage(f"{template.address} with too few arguments", f"got {list(args)!r}")
            user = self._int(address, fields.get("user", self.default_user))
            if template.on != "joint":
                return [UserEvent(user, "new" if template.on == "new_user" else "lost")]
            xyz = _floats(address, [self._number(fields[k]) for k in ("x", "y", "z")], 3)
            confidence = float(self._number(fields.get("confidence", 1.0)))
            return [Reading(user, _sided(str(fields["joint"])), tuple(c * self.scale for c in xyz), confidence)]
        raise BadMessage("address matching no template", address)

    @staticmethod
    def _number(value: Any) -> Any:
        if isinstance(value, str):
            try:
                return float(value)
            except ValueError:
                return value
        return value

    @staticmethod
    def _int(address: str, value: Any) -> int:
        try:
            return int(value)
        except (TypeError, ValueError):
            raise BadMessage(f"{address} with a user that is not a number", f"got {value!r}") from None
