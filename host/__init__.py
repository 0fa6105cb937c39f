"""issv host: the frozen core. Plugins import what they need from here and nowhere else in host."""
from host.contracts import Backend, DeviceInfo, Effect, NoOptions, Plugin, PluginUnavailable, Source, Stage
from host.hookspecs import hookimpl
from host.model import (
    CANONICAL_GESTURES,
    ColourFrame,
    DepthFrame,
    Frame,
    Gesture,
    GestureState,
    GestureType,
    Hand,
    HandState,
    Intrinsics,
    JOINTS,
    Joint,
    Side,
    Truth,
    TruthGesture,
    User,
    Vec3,
)
from host.callbacks import SimpleOpenNIEffect

__version__ = "0.1.0"

__all__ = [
    "Backend", "CANONICAL_GESTURES", "ColourFrame", "DepthFrame", "DeviceInfo", "Effect", "Frame", "Gesture",
    "GestureState", "GestureType", "Hand", "HandState", "Intrinsics", "JOINTS", "Joint", "NoOptions", "Plugin",
    "PluginUnavailable", "SimpleOpenNIEffect", "Side", "Source", "Stage", "Truth", "TruthGesture", "User", "Vec3",
    "hookimpl", "__version__",
]
