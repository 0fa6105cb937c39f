"""FAKE of PyNuitrack.py_nuitrack (Nuitrack's official Python bindings): tests only.

Mirrors the API documented in the Nuitrack SDK (PythonNuitrack-beta/README.MD): Nuitrack()
with init(), get_device_list() (devices with get_name(), get_serial_number(), get_activation(),
activate(key)), set_device(), get_version(), get_license(), create_modules(), run(), update(),
get_skeleton() (timestamp in us, skeletons_num, skeletons: each a tuple of user_id then the
joints, reachable by name, each joint with type, confidence, real (x, y, z mm), projection,
orientation), get_depth_data() (uint16 mm; empty before the first frame), get_color_data(),
set_config_value(), release().

Test hook: `fake_sensors`, the sensors "connected", each playing a list of FakeNuitrackFrame.
Like Nuitrack, depth comes in one buffer that the next update overwrites. An unlicensed sensor
stops after 3 minutes of its own time: update() raises. How the real wheel surfaces Nuitrack's
LicenseNotAcquiredException in Python is not documented; the fake raises an exception named
after it (the adapter recognises the name in the type or the message). Past its last frame a
sensor delivers no depth (as one unplugged).
"""
from collections import namedtuple
from dataclasses import dataclass, field

import numpy as np

JOINTS = ("head", "neck", "torso", "waist", "left_collar", "left_shoulder", "left_elbow", "left_wrist",
          "left_hand", "right_collar", "right_shoulder", "right_elbow", "right_wrist", "right_hand",
          "left_hip", "left_knee", "left_ankle", "right_hip", "right_knee", "right_ankle")
UNLICENSED_S = 180.0

Joint = namedtuple("Joint", "type confidence real projection orientation")
Skeleton = namedtuple("Skeleton", ("user_id",) + JOINTS)
SkeletonResult = namedtuple("SkeletonResult", "timestamp skeletons_num skeletons")


class LicenseNotAcquiredException(Exception):
    """FAKE: stands for Nuitrack's tdv::nuitrack::LicenseNotAcquiredException as raised by the wheel."""


@dataclass
class FakeNuitrackFrame:
    t: float  # seconds
    depth: object  # numpy uint16 (H, W)
    users: dict = field(default_factory=dict)  # user id -> {joint name: ((x, y, z) mm, confidence)}


@dataclass
class FakeSensor:
    name: str
    serial: str
    frames: list
    licensed: bool = True


fake_sensors = []
fake_instances = []  # every Nuitrack() made, to check that it was released


class Device(object):
    def __init__(self, sensor):
        self._sensor = sensor

    def get_name(self):
        return self._sensor.name

    def get_serial_number(self):
        return self._sensor.serial

    def get_activation(self):
        return "ACTIVATED" if self._sensor.licensed else "NONE"

    def activate(self, key):
        self._sensor.licensed = True


def _joint(index, value):
    real, confidence = value if value is not None else ((0.0, 0.0, 0.0), 0.0)
    return Joint(index, float(confidence), np.array(real, float), np.zeros(3), np.eye(3))


class Nuitrack(object):
    def __init__(self):
        self._state = "created"
        self._device = None
        self._depth = np.zeros((0, 0), np.uint16)
        self._skeletons = SkeletonResult(0, 0, [])
        fake_instances.append(self)

    def init(self, config_path=""):
        self._state = "initialized"

    def get_device_list(self):
        self._need("initialized")
        return [Device(s) for s in fake_sensors]

    def set_device(self, device):
        self._device = device._sensor

    def set_config_value(self, key, value):
        pass

    def get_version(self):
        return "FAKE-0.38"

    def get_license(self):
        return "FAKE licence" if self._device is not None and self._device.licensed else "FAKE: none"

    def create_modules(self):
        self._need("initialized")
        if self._device is None:
            self._device = fake_sensors[0] if fake_sensors else None
        if self._device is None:
            raise RuntimeError("DeviceNotDetectedException")
        self._state = "modules"

    def run(self):
        self._need("modules")
        self._state, self._index = "running", -1

    def update(self):
        self._need("running")
        self._index += 1
        frames = self._device.frames
        if self._index >= len(frames):
            self._depth = np.zeros((0, 0), np.uint16)
            return
        frame = frames[self._index]
        if not self._device.licensed and frame.t - frames[0].t > UNLICENSED_S:
            raise LicenseNotAcquiredException("LicenseNotAcquired")
        if self._depth.shape != frame.depth.shape:
            self._depth = np.zeros(frame.depth.shape, np.uint16)
        self._depth[...] = frame.depth  # one buffer, overwritten by every update
        skeletons = [Skeleton(user, *(_joint(i, joints.get(name)) for i, name in enumerate(JOINTS)))
                     for user, joints in frame.users.items()]
        self._skeletons = SkeletonResult(int(frame.t * 1e6), len(skeletons), skeletons)

    def get_skeleton(self):
        return self._skeletons

    def get_depth_data(self):
        return self._depth

    def get_color_data(self):
        return np.zeros((0, 0, 3), np.uint8)

    def release(self):
        self._state = "released"
        self.fake_released = True

    def _need(self, state):
        order = ("created", "initialized", "modules", "running")
        if self._state == "released" or order.index(self._state) < order.index(state):
            raise RuntimeError("FAKE Nuitrack: called before %s (state %s)" % (state, self._state))
