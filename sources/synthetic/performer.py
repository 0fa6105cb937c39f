"""The performer's body: proportions from its height, joints from a posture, shapes to draw.

Segment lengths are fractions of standing height from anthropometric tables (Drillis & Contini
1966, as tabulated in Winter, "Biomechanics and Motor Control of Human Movement"): shoulder at
0.818 H, hip at 0.530 H, upper arm 0.186 H, forearm 0.146 H, hand 0.108 H, thigh 0.245 H,
shank 0.246 H. Nothing here is tuned to a person: a taller performer is simply scaled.

Body frame: origin on the floor under the pelvis, axes (right, up, forward) from the performer's
point of view. `Pose` maps it into camera millimetres (docs/architecture.md: x towards the image's right,
y up, z away from the camera); whether the performer's right shows on the image's right is the
`mirrored` flag.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from host import JOINTS, Side, Vec3
from sources.synthetic.render import Capsule, Ellipsoid, Shape

UP = np.array([0.0, 1.0, 0.0])
SIDES = (Side.LEFT, Side.RIGHT)


def sign(side: Side) -> float:
    """+1 for the performer's right, -1 for the left: the body frame's x of that side."""
    return 1.0 if side is Side.RIGHT else -1.0


@dataclass(frozen=True)
class Posture:
    """What the choreography decides at one instant; the performer turns it into joints.

    `x`, `z`: where the pelvis stands, camera mm. `yaw`: radians; 0 faces the camera, +pi/2 faces
    +x. `hands`: palm-centre targets in the body frame. `gait_phase` counts strides;
    `gait`: 0 (standing) to 1 (full walking swing) for the legs.
    """

    x: float
    z: float
    yaw: float
    hands: dict[Side, np.ndarray]
    gait_phase: float = 0.0
    gait: float = 0.0


@dataclass(frozen=True)
class Body:
    """Segment lengths and radii (mm) of a performer of standing height `height`."""

    height: float

    def __getattr__(self, name: str) -> float:
        try:
            return _FRACTIONS[name] * self.height
        except KeyError:
            raise AttributeError(name) from None

    @property
    def reach(self) -> float:
        """Shoulder to palm centre with the arm straight."""
        return self.upper_arm + self.forearm + PALM * self.hand

    def shoulder(self, side: Side) -> np.ndarray:
        return np.array([sign(side) * self.shoulder_half, self.shoulder_y, 0.0])

    def rest(self, side: Side) -> np.ndarray:
        """Palm centre with the arm hanging relaxed, elbow slightly bent, hand a little forward."""
        return np.array([sign(side) * self.rest_out, self.rest_y, self.rest_forward])


# Fractions of height. Lengths from the tables above; radii are typical half-thicknesses.
_FRACTIONS = {
    "head_y": 0.935, "head_rx": 0.044, "head_ry": 0.065, "head_rz": 0.055,
    "neck_y": 0.870, "neck_r": 0.030,
    "shoulder_y": 0.818, "shoulder_half": 0.115, "shoulder_r": 0.032,
    "chest_y": 0.675, "chest_rx": 0.105, "chest_ry": 0.170, "chest_rz": 0.065,
    "torso_y": 0.650,
    "pelvis_y": 0.540, "pelvis_rx": 0.100, "pelvis_ry": 0.070, "pelvis_rz": 0.065,
    "hip_y": 0.530, "hip_half": 0.055,
    "upper_arm": 0.186, "upper_arm_r": 0.025, "forearm": 0.146, "forearm_r": 0.020,
    "hand": 0.108, "hand_r": 0.021,
    "thigh": 0.245, "thigh_r": 0.040, "shank": 0.246, "shank_r": 0.028,
    "ankle_y": 0.039, "foot": 0.152, "foot_r": 0.020,
    "rest_out": 0.140, "rest_y": 0.450, "rest_forward": 0.035,
}
PALM = 0.45  # the palm centre lies this far along the hand from the wrist
HIP_SWING = np.radians(22.0)  # hip flexion amplitude of a normal walk
KNEE_SWING = np.radians(55.0)  # peak knee flexion during the swing phase
ELBOW_POLE = np.array([0.45, -1.0, -0.35])  # elbows point out, down and back (x is per side)


_TRUTH_NAMES = {"neck": "shoulder_centre", "left_hand": "left_palm", "right_hand": "right_palm",
                "left_foot": "left_ankle", "right_foot": "right_ankle"}


@dataclass(frozen=True)
class Pose:
    """Every joint in camera millimetres, and the shapes that make the body's surface."""

    joints: dict[str, np.ndarray]
    shapes: list[Shape]

    def point(self, name: str) -> Vec3:
        x, y, z = self.joints[name]
        return (float(x), float(y), float(z))

    @property
    def hands(self) -> dict[Side, Vec3]:
        return {side: self.point(f"{side.value}_palm") for side in SIDES}

    @property
    def body(self) -> dict[str, Vec3]:
        """Every joint of host.JOINTS: the neck is the shoulder centre (as Kinect's), a hand the
        palm centre (as the truth hands), a foot the ankle (as OpenNI's)."""
        return {name: self.point(_TRUTH_NAMES.get(name, name)) for name in JOINTS}


class Performer:
    """Kinematics: a posture becomes joints (arm IK, leg swing) and then shapes."""

    def __init__(self, body: Body, mirrored: bool, floor_y: float) -> None:
        self.body = body
        self.chirality = 1.0 if mirrored else -1.0
        self.floor_y = floor_y

    def pose(self, posture: Posture) -> Pose:
        b = self.body
        local: dict[str, np.ndarray] = {
            "head": np.array([0.0, b.head_y, 0.0]),
            "neck": np.array([0.0, b.neck_y, 0.0]),
            "torso": np.array([0.0, b.torso_y, 0.0]),
            "chest": np.array([0.0, b.chest_y, 0.0]),
            "pelvis": np.array([0.0, b.pelvis_y, 0.0]),
        }
        for side in SIDES:
            local.update(self._arm(side, posture.hands[side]))
        drop = 0.0
        for side in SIDES:
            leg = self._leg(side, posture)
            local.update(leg)
            drop = max(drop, b.ankle_y - leg[f"{side.value}_ankle"][1])
        # The lower foot stays on the floor: the whole body sinks as much as a swinging leg lifts it.
        rotation = self._rotation(posture.yaw)
        origin = np.array([posture.x, self.floor_y - drop, posture.z])
        joints = {name: origin + rotation @ p for name, p in local.items()}
        joints["shoulder_centre"] = (joints["left_shoulder"] + joints["right_shoulder"]) / 2
        return Pose(joints, self._shapes(joints, rotation))

    def _rotation(self, yaw: float) -> np.ndarray:
        """Columns: the body's right, up and forward axes in camera coordinates."""
        forward = np.array([np.sin(yaw), 0.0, -np.cos(yaw)])
        right = self.chirality * np.cross(forward, UP)
        return np.column_stack([right, UP, forward])

    def _arm(self, side: Side, palm: np.ndarray) -> dict[str, np.ndarray]:
        """Two-bone inverse kinematics from the shoulder to the palm centre, elbow towards a pole."""
        b = self.body
        shoulder = b.shoulder(side)
        upper, lower = b.upper_arm, b.forearm + PALM * b.hand
        offset = palm - shoulder
        dist = float(np.linalg.norm(offset))
        reach = float(np.clip(dist, abs(upper - lower) + 1.0, upper + lower - 1.0))
        axis = offset / max(dist, 1e-6)
        palm = shoulder + axis * reach  # a target out of reach is met with a straight arm
        along = (upper**2 - lower**2 + reach**2) / (2 * reach)
        out = np.sqrt(max(upper**2 - along**2, 0.0))
        pole = ELBOW_POLE * np.array([sign(side), 1.0, 1.0])
        pole = pole - axis * (pole @ axis)
        elbow = shoulder + axis * along + pole / np.linalg.norm(pole) * out
        direction = (palm - elbow) / np.linalg.norm(palm - elbow)
        wrist = elbow + direction * b.forearm
        name = side.value
        return {f"{name}_shoulder": shoulder, f"{name}_elbow": elbow, f"{name}_wrist": wrist,
                f"{name}_palm": palm, f"{name}_fingers": wrist + direction * b.hand}

    def _leg(self, side: Side, posture: Posture) -> dict[str, np.ndarray]:
        """A sagittal-plane leg: hip flexion swings sinusoidally, the knee bends in the swing phase."""
        b = self.body
        phase = 2 * np.pi * posture.gait_phase + (0.0 if side is Side.RIGHT else np.pi)
        hip_angle = posture.gait * HIP_SWING * np.sin(phase)
        knee_angle = posture.gait * KNEE_SWING * max(0.0, np.cos(phase)) ** 2
        hip = np.array([sign(side) * b.hip_half, b.hip_y, 0.0])
        knee = hip + b.thigh * np.array([0.0, -np.cos(hip_angle), np.sin(hip_angle)])
        shank = hip_angle - knee_angle
        ankle = knee + b.shank * np.array([0.0, -np.cos(shank), np.sin(shank)])
        toe = ankle + np.array([0.0, -0.5 * b.ankle_y, 0.7 * b.foot])
        name = side.value
        return {f"{name}_hip": hip, f"{name}_knee": knee, f"{name}_ankle": ankle, f"{name}_toe": toe}

    def _shapes(self, j: dict[str, np.ndarray], rotation: np.ndarray) -> list[Shape]:
        b = self.body
        axes = rotation.T  # rows: right, up, forward
        shapes: list[Shape] = [
            Ellipsoid(j["head"], axes, (b.head_rx, b.head_ry, b.head_rz)),
            Ellipsoid(j["chest"], axes, (b.chest_rx, b.chest_ry, b.chest_rz)),
            Ellipsoid(j["pelvis"], axes, (b.pelvis_rx, b.pelvis_ry, b.pelvis_rz)),
            Capsule(j["neck"], j["chest"] + axes[1] * b.chest_ry * 0.6, b.neck_r),
            Capsule(j["left_shoulder"], j["right_shoulder"], b.shoulder_r),
        ]
        for s in ("left", "right"):
            shapes += [
                Capsule(j[f"{s}_shoulder"], j[f"{s}_elbow"], b.upper_arm_r),
                Capsule(j[f"{s}_elbow"], j[f"{s}_wrist"], b.forearm_r),
                Capsule(j[f"{s}_wrist"], j[f"{s}_fingers"], b.hand_r),
                Capsule(j[f"{s}_hip"], j[f"{s}_knee"], b.thigh_r),
                Capsule(j[f"{s}_knee"], j[f"{s}_ankle"], b.shank_r),
                Capsule(j[f"{s}_ankle"], j[f"{s}_toe"], b.foot_r),
            ]
        return shapes

