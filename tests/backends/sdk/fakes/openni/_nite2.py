"""FAKE of openni._nite2 (the ctypes layer, used as `nite2.c_api`): the same structures and enums."""
import ctypes

from openni.utils import CEnum


def _members(cls):
    for name, value in list(vars(cls).items()):
        if name.startswith("NITE_"):
            setattr(cls, name, cls(value))
    return cls


@_members
class NiteStatus(CEnum):
    NITE_STATUS_OK = 0
    NITE_STATUS_ERROR = 1
    NITE_STATUS_BAD_USER_ID = 2
    NITE_STATUS_OUT_OF_FLOW = 3


@_members
class NiteGestureType(CEnum):
    NITE_GESTURE_WAVE = 0
    NITE_GESTURE_CLICK = 1
    NITE_GESTURE_HAND_RAISE = 2


@_members
class NiteGestureState(CEnum):
    NITE_GESTURE_STATE_NEW = 1
    NITE_GESTURE_STATE_IN_PROGRESS = 2
    NITE_GESTURE_STATE_COMPLETED = 4


@_members
class NiteHandState(CEnum):
    NITE_HAND_STATE_LOST = 0
    NITE_HAND_STATE_NEW = 1
    NITE_HAND_STATE_TRACKED = 2
    NITE_HAND_STATE_TOUCHING_FOV = 4


NiteHandId = ctypes.c_short


class NitePoint3f(ctypes.Structure):
    _fields_ = [("x", ctypes.c_float), ("y", ctypes.c_float), ("z", ctypes.c_float)]


class NiteHandData(ctypes.Structure):
    _fields_ = [("id", NiteHandId), ("position", NitePoint3f), ("state", ctypes.c_int)]


class NiteGestureData(ctypes.Structure):
    _fields_ = [("type", NiteGestureType), ("currentPosition", NitePoint3f), ("state", ctypes.c_int)]
