"""FAKE of openni.nite2 (PyPI `openni` 2.3.0): NiTE2's HandTracker playing a scripted scene.

Mirrors the real module: initialize(dll_directories) looks for libNiTE2.so in the folders and
raises InitializationError when it cannot be loaded; HandTracker(device) with
start/stop_gesture_detection, start_hand_tracking(position) -> HandId, stop_hand_tracking,
stop_all_hand_tracking, stop_all_gesture_detection, read_frame() -> HandTrackerFrame (.hands and
.gestures are lists of raw NiteHandData / NiteGestureData structures, as in the real bindings;
.depth_frame, .timestamp in us, .frameIndex), convert_hand_coordinates_to_depth; HandData and
GestureData wrappers with the real (==) comparisons.

NiTE's behaviour is simulated from the scene: gestures are reported only for the types whose
detection was started; a hand is reported only after start_hand_tracking near one of the
scene's hands: NEW on its first frame, then TRACKED (| TOUCHING_FOV when the scene says so),
LOST once when it leaves the scene, then no more. Releasing a frame wipes its memory, as NiTE
reuses it. The real NiTE blocks in read_frame() at the end of a recording; the fake raises.
A fake runtime is a folder holding a libNiTE2.so whose content is FAKE_RUNTIME.
"""
import ctypes
import os
from dataclasses import dataclass, field

from openni import _nite2 as c_api
from openni import openni2
from openni.utils import HandleObject, InitializationError, NiteError

GestureType = c_api.NiteGestureType
HandId = c_api.NiteHandId
Point3f = c_api.NitePoint3f
FAKE_RUNTIME = b"FAKE NiTE2 runtime"
SAME_HAND_MM = 200.0  # start_hand_tracking finds a scene hand this close to the position

_nite2_initialized = False
loaded_dll_directory = None


@dataclass
class FakeNiteFrame:
    """What NiTE sees in one frame: depth, the performer's hands, the gestures it recognises."""

    depth: object  # numpy uint16 (H, W) mm
    hands: dict = field(default_factory=dict)  # scene hand key -> (x, y, z) mm
    touching_fov: set = field(default_factory=set)  # scene hand keys at the border
    gestures: list = field(default_factory=list)  # (type name, (x, y, z), state name)


@dataclass
class FakeScene:
    frames: list
    intrinsics: tuple = (525.0, 525.0, 320.0, 240.0)  # fx, fy, cx, cy
    fps: float = 30.0
    unplugged_at: int | None = None  # from this frame on, reading fails as NiTE does (NiteError)


def initialize(dll_directories=()):
    global _nite2_initialized, loaded_dll_directory
    if _nite2_initialized:
        return
    if isinstance(dll_directories, str):
        dll_directories = [dll_directories]
    if not openni2.is_initialized():
        openni2.initialize()
    problems = []
    for folder in dll_directories:
        path = os.path.join(folder, "libNiTE2.so")
        if not os.path.isfile(path):
            problems.append((path, "file does not exist"))
            continue
        with open(path, "rb") as f:
            if f.read() != FAKE_RUNTIME:
                problems.append((path, "OSError('invalid ELF header')"))
                continue
        loaded_dll_directory, _nite2_initialized = folder, True
        return
    raise InitializationError("NiTE2 could not be loaded:\n    %s" % "\n    ".join("%s: %s" % p for p in problems))


def is_initialized():
    return _nite2_initialized


def unload():
    global _nite2_initialized
    _nite2_initialized = False


class GestureData(object):
    def __init__(self, gesture):
        self._gesture = gesture
        self.type, self.currentPosition, self.state = gesture.type, gesture.currentPosition, gesture.state

    def is_complete(self):
        return self.state == c_api.NiteGestureState.NITE_GESTURE_STATE_COMPLETED

    def is_in_progress(self):
        return self.state == c_api.NiteGestureState.NITE_GESTURE_STATE_IN_PROGRESS


class HandData(object):
    def __init__(self, handdata):
        self._handdata = handdata
        self.id, self.position, self.state = handdata.id, handdata.position, handdata.state

    def is_new(self):
        return self.state == c_api.NiteHandState.NITE_HAND_STATE_NEW

    def is_lost(self):
        return self.state == c_api.NiteHandState.NITE_HAND_STATE_LOST

    def is_tracking(self):
        return self.state == c_api.NiteHandState.NITE_HAND_STATE_TRACKED

    def is_touching_fov(self):
        return self.state == c_api.NiteHandState.NITE_HAND_STATE_TOUCHING_FOV


class HandTrackerFrame(HandleObject):
    def __init__(self, hands, gestures, depth_frame, timestamp, index):
        self._hand_array = (c_api.NiteHandData * max(1, len(hands)))(*hands)
        self._gesture_array = (c_api.NiteGestureData * max(1, len(gestures)))(*gestures)
        self.handCount, self.gestureCount = len(hands), len(gestures)
        self._depth_frame, self._timestamp, self._index = depth_frame, timestamp, index
        HandleObject.__init__(self, True)

    @property
    def depth_frame(self):
        return self._depth_frame

    @property
    def timestamp(self):
        return self._timestamp

    @property
    def frameIndex(self):
        return self._index

    @property
    def hands(self):
        return [self._hand_array[i] for i in range(self.handCount)]

    @property
    def gestures(self):
        return [self._gesture_array[i] for i in range(self.gestureCount)]

    def _close(self):  # NiTE takes the memory back
        ctypes.memset(self._hand_array, 0, ctypes.sizeof(self._hand_array))
        ctypes.memset(self._gesture_array, 0, ctypes.sizeof(self._gesture_array))
        self._depth_frame.close()


class HandTracker(HandleObject):
    def __init__(self, device):
        if not _nite2_initialized:
            raise InitializationError("NiTE2 not initialized")
        self.device = device if device else openni2.Device.open_any()
        self.fake_scene = self.device.fake_scene
        self.fake_detecting = set()  # gesture type values
        self.fake_tracked = {}  # NiTE hand id -> scene hand key
        self.fake_new = set()
        self._next_id = 1
        self._index = -1
        HandleObject.__init__(self, True)

    @classmethod
    def open_any(cls):
        return cls(None)

    def _close(self):
        self.fake_closed = True

    def start_gesture_detection(self, gesture_type):
        self.fake_detecting.add(int(gesture_type))

    def stop_gesture_detection(self, gesture_type):
        self.fake_detecting.discard(int(gesture_type))

    def stop_all_gesture_detection(self):
        self.fake_detecting.clear()

    def start_hand_tracking(self, *position):
        if len(position) == 3:
            position = Point3f(*position)
        elif len(position) == 1:
            position = position[0]
        else:
            raise TypeError("Either Point3f or three values required")
        new_hand_id = HandId(self._next_id)
        self._next_id += 1
        frame = self.fake_scene.frames[max(self._index, 0)]
        near = [k for k, p in frame.hands.items()
                if sum((a - b) ** 2 for a, b in zip(p, (position.x, position.y, position.z))) <= SAME_HAND_MM ** 2]
        self.fake_tracked[new_hand_id.value] = near[0] if near else None
        self.fake_new.add(new_hand_id.value)
        return new_hand_id

    def stop_hand_tracking(self, handid):
        self.fake_tracked.pop(int(handid), None)

    def stop_all_hand_tracking(self):
        self.fake_tracked.clear()

    def read_frame(self):
        self._index += 1
        if self.fake_scene.unplugged_at is not None and self._index >= self.fake_scene.unplugged_at:
            raise NiteError(c_api.NiteStatus.NITE_STATUS_ERROR)  # what nite_call raises on a bad status
        if self._index >= len(self.fake_scene.frames):
            raise RuntimeError("FAKE NiTE2: read past the end of the scene (the real NiTE2 would block here)")
        scene = self.fake_scene.frames[self._index]
        hands = []
        for hid, key in list(self.fake_tracked.items()):
            if key not in scene.hands:
                hands.append(c_api.NiteHandData(hid, Point3f(0, 0, 0), c_api.NiteHandState.NITE_HAND_STATE_LOST))
                del self.fake_tracked[hid]
                continue
            state = c_api.NiteHandState.NITE_HAND_STATE_TRACKED.value
            if hid in self.fake_new:
                state |= c_api.NiteHandState.NITE_HAND_STATE_NEW.value
                self.fake_new.discard(hid)
            if key in scene.touching_fov:
                state |= c_api.NiteHandState.NITE_HAND_STATE_TOUCHING_FOV.value
            hands.append(c_api.NiteHandData(hid, Point3f(*scene.hands[key]), state))
        gestures = [c_api.NiteGestureData(getattr(GestureType, kind), Point3f(*pos),
                                          getattr(c_api.NiteGestureState, state).value)
                    for kind, pos, state in scene.gestures if int(getattr(GestureType, kind)) in self.fake_detecting]
        timestamp = int(1_000_000 * (5.0 + self._index / self.fake_scene.fps))
        depth = openni2.VideoFrame(scene.depth.copy(), timestamp, self._index + 1)
        return HandTrackerFrame(hands, gestures, depth, timestamp, self._index + 1)

    def convert_hand_coordinates_to_depth(self, x, y, z):
        fx, fy, cx, cy = self.fake_scene.intrinsics
        return x * fx / z + cx, cy - y * fy / z
