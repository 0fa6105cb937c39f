"""The FAKE `openni` package has the real PyPI bindings' names and signatures where the adapter uses them.

The real `openni` package is pure Python over ctypes: it imports without NiTE2 or OpenNI2, so
its API can be read here (its libraries are loaded only by initialize()). PyNuitrack is a
compiled wheel that cannot be installed here: its fake follows the SDK's documentation.
"""
from __future__ import annotations

import importlib
import inspect

import pytest

USED = {  # module -> attribute paths the adapter and the fakes rely on
    "openni.nite2": ["initialize", "is_initialized", "HandTracker.__init__", "HandTracker.start_gesture_detection",
                     "HandTracker.stop_gesture_detection", "HandTracker.start_hand_tracking",
                     "HandTracker.stop_hand_tracking", "HandTracker.stop_all_hand_tracking",
                     "HandTracker.stop_all_gesture_detection", "HandTracker.read_frame",
                     "HandTracker.convert_hand_coordinates_to_depth", "HandTracker.close",
                     "HandTrackerFrame.hands", "HandTrackerFrame.gestures", "HandTrackerFrame.depth_frame",
                     "HandTrackerFrame.timestamp", "HandTrackerFrame.frameIndex", "HandTrackerFrame.close",
                     "HandData.is_new", "HandData.is_tracking", "HandData.is_lost", "HandData.is_touching_fov",
                     "GestureData.is_complete", "GestureData.is_in_progress", "Point3f", "HandId", "GestureType",
                     "c_api.NiteGestureType", "c_api.NiteHandState", "c_api.NiteGestureState"],
    "openni.openni2": ["initialize", "is_initialized", "Device.__init__", "Device.open_any", "Device.open_file",
                       "Device.get_device_info", "Device.close", "VideoFrame.get_buffer_as_uint16",
                       "InitializationError"],
    "openni.utils": ["OpenNIError.__init__", "NiteError.__init__", "InitializationError"],
}
ENUMS = ["NiteGestureType", "NiteHandState", "NiteGestureState", "NiteStatus"]
STRUCTS = ["NitePoint3f", "NiteHandData", "NiteGestureData"]


def _get(module, path: str):
    obj = module
    for part in path.split("."):
        obj = getattr(obj, part)
    return obj


def _params(obj):
    """A function's parameter names, else what the thing is (a property, a class)."""
    if isinstance(obj, property):
        return "property"
    if inspect.isclass(obj):
        return "class"
    return [p.name for p in inspect.signature(obj).parameters.values()]


def _api() -> dict:
    api = {}
    for name, paths in USED.items():
        module = importlib.import_module(name)
        for path in paths:
            api[f"{name}:{path}"] = _params(_get(module, path))
    c_api = importlib.import_module("openni.nite2").c_api
    for enum in ENUMS:
        members = getattr(c_api, enum)
        api[enum] = {k: int(getattr(members, k)) for k in dir(members) if k.startswith("NITE_")}
    for struct in STRUCTS:
        api[struct] = [f[0] for f in getattr(c_api, struct)._fields_]
    return api


try:
    REAL = _api()  # read at import, before the fixture hides the real package
except ImportError:  # pragma: no cover - the project depends on `openni`
    REAL = None


@pytest.mark.skipif(REAL is None, reason="the real PyPI `openni` package is not installed")
def test_the_fake_openni_mirrors_the_real_bindings(fake_sdks):
    fake = _api()
    assert importlib.import_module("openni").__file__.startswith(str(fake_sdks))
    assert fake == REAL
