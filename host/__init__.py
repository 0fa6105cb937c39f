"""issv host: the frozen core. Plugins import what they need from here, and from the few public
host modules listed in PUBLIC_MODULES, nowhere else in host (docs/architecture.md, Plugins and
the import rule; tests/test_imports.py checks it)."""
from host.contracts import (Backend, DeviceInfo, Effect, NoOptions, Plugin, PluginUnavailable, Recognizer,
                            Source, Stage, Update, frames_of)
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
    UserTruth,
    User,
    Vec3,
)
from host.callbacks import SimpleOpenNIEffect
from host.palette import USER_COLOURS, user_colour
from host.loop import profile_source

__version__ = "0.1.0"

#: Host modules a plugin may import besides `host` itself: each has one job a plugin needs.
PUBLIC_MODULES = (
    "host.options",  # types for plugin Options (profile-relative paths, colours)
    "host.errors",  # UserError: one clear line for the user
    "host.recording",  # the recording format (issv-recording/1): read and write .mcap
    "host.compression",  # zstd contexts, one per thread
    "host.devices",  # the OpenNI2 runtime, shared by what opens OpenNI2 devices and files
    "host.app",  # for plugin commands: a profile's source and backend through the frame loop
    "host.audio",  # the show's sound (level, spectrum, samples) for audio-reactive effects
    "host.osc",  # OSC 1.0 encoding and message-template placeholders (sent by effects, read by backends)
)

__all__ = [
    "Backend", "CANONICAL_GESTURES", "ColourFrame", "DepthFrame", "DeviceInfo", "Effect", "Frame", "Gesture",
    "GestureState", "GestureType", "Hand", "HandState", "Intrinsics", "JOINTS", "Joint", "NoOptions", "PUBLIC_MODULES",
    "Plugin", "PluginUnavailable", "Recognizer", "SimpleOpenNIEffect", "Side", "Source", "Stage", "Truth",
    "TruthGesture", "USER_COLOURS", "Update", "User", "UserTruth", "Vec3", "frames_of", "hookimpl", "profile_source",
    "user_colour", "__version__",
]
