"""`openiss-nite` over the real NiTE2 runtime, through the PyPI `openni` bindings (openni.nite2).

NiTE2 is closed and no longer distributed: it runs only where its Redist folder (libNiTE2.so and
its NiTE2/ data) is installed, found through the option `nite2_redist` or $NITE2_REDIST64 /
$NITE2_REDIST (the variables the bindings themselves read). It reads depth from an OpenNI2
device: the `oni` source's recording, or a sensor named by the option `device`. Anywhere else
the parent class runs: the open engine in NiTE mode.

What this adapter does that the thesis' OINiTEGestureTracker did not:
- NiTE's focus semantics kept exactly: a completed wave or click starts hand tracking at the
  gesture's position (`start_hand_tracking`), and that gesture carries the new hand's id.
- NiTE's hand states are bit flags (NEW|TRACKED, TRACKED|TOUCHING_FOV); the bindings' HandData
  compares them with ==, which misses combined states, so the bits are read here.
- Every gesture has a position (NiTE's `currentPosition`) and the hand nearest to it, if any.
- Depth, hands and gestures are copied out of NiTE's frame, then the frame is released at once.
- start/stop methods call NiTE's start/stop_gesture_detection and stop_all_hand_tracking.
- Coordinates: NiTE reports OpenNI2 world coordinates in millimetres, x towards the depth
  image's right, y up, z away from the sensor; that is exactly our camera frame (docs/architecture.md), so
  `nite_to_camera` passes them through unchanged, on purpose and in one place (no silent flips).
"""
from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numpy as np
from pydantic import Field

from backends.engine.backend import EngineOptions, OpenISSNiteBackend
from backends.sdk.adapter import SdkBackend, SdkFrame, SdkStopped, SdkUnavailable
from host import DepthFrame, Gesture, GestureState, Hand, HandState, Intrinsics, Side, Source, Vec3
from host.devices import INSTALL as OPENNI2_INSTALL
from host.devices import bindings_dir, find_runtime
from host.options import ProfilePath

NITE2_LIBRARY = {"win32": "NiTE2.dll", "darwin": "libNiTE2.dylib"}.get(sys.platform, "libNiTE2.so")
NITE2_HELP = (f"set NITE2_REDIST, or the backend option nite2_redist, to the NiTE2 Redist folder "
              f"holding {NITE2_LIBRARY}")
#: NiTE's gesture types (openni.nite2.c_api.NiteGestureType) by our canonical name.
NITE_GESTURES = {"wave": "NITE_GESTURE_WAVE", "click": "NITE_GESTURE_CLICK", "hand_raise": "NITE_GESTURE_HAND_RAISE"}
# NiteHandState / NiteGestureState bit flags (NiTE.h)
HAND_LOST, HAND_NEW, HAND_TRACKED, HAND_TOUCHING_FOV = 0, 1, 2, 4
GESTURE_NEW, GESTURE_IN_PROGRESS, GESTURE_COMPLETED = 1, 2, 4
SAME_HAND_MM = 150.0  # a gesture this close to a tracked hand is that hand's (no second hand there)
IN_PROGRESS_REPEAT_S = 1.0  # NiTE repeats IN_PROGRESS every frame; we report it once per attempt


class NiteOptions(EngineOptions):
    """The open engine's options (used when NiTE2 is absent) plus where NiTE2 and its sensor are."""

    nite2_redist: ProfilePath | None = Field(None, description=(
        f"the NiTE2 Redist folder (holding {NITE2_LIBRARY}); default $NITE2_REDIST64 or $NITE2_REDIST"))
    device: str | None = Field(None, description=(
        "an OpenNI2 device for NiTE2: 'any' (the first sensor) or a device URI; "
        "default: the `oni` source's recording. A sensor's image is taken as mirrored (OpenNI2's default)"))


def find_nite2(configured: str | None) -> Path | None:
    """The NiTE2 Redist folder: the option first, then the variables the bindings read."""
    for folder in (configured, os.environ.get("NITE2_REDIST64"), os.environ.get("NITE2_REDIST")):
        if folder and (Path(folder) / NITE2_LIBRARY).is_file():
            return Path(folder)
    return None


def nite_to_camera(point) -> Vec3:
    """NiTE world (mm; x image-right, y up, z away) -> ours: the same axes, so unchanged."""
    return (float(point.x), float(point.y), float(point.z))


def hand_state(bits: int) -> HandState:
    """NiTE's flags -> one state: LOST (no flag), NEW first, then TOUCHING_FOV, else TRACKING."""
    if bits == HAND_LOST:
        return HandState.LOST
    if bits & HAND_NEW:
        return HandState.NEW
    if bits & HAND_TOUCHING_FOV:
        return HandState.TOUCHING_FOV
    return HandState.TRACKING


class NiteSession:
    """One NiTE2 HandTracker on one OpenNI2 device; frames in our model."""

    def __init__(self, backend: "NiteBackend", redist: Path, device, owns_device: bool,
                 mirrored: bool, frames: int) -> None:
        from openni import nite2
        from openni.utils import NiteError, OpenNIError

        self.nite2, self.errors = nite2, (NiteError, OpenNIError)
        self.device, self.owns_device, self.mirrored = device, owns_device, mirrored
        self.last_frame = frames  # a recording played once ends at frame index `frames` (1-based); -1: endless
        try:
            self.tracker = nite2.HandTracker(device)
        except Exception as error:  # NiteError (a status code) or a ctypes failure
            raise SdkUnavailable(f"NiTE2 cannot track hands on this device: {error!r}") from None
        self.types = {name: getattr(nite2.c_api.NiteGestureType, native) for name, native in NITE_GESTURES.items()}
        self.names = {int(t): name for name, t in self.types.items()}
        self.dictionary = backend.dictionary  # canonical name -> our native type (NiTE's three)
        self.focus = backend.focus_gestures  # they start hand tracking where they happened
        self.detecting: set[str] = set()
        self.tracking = False
        self.intrinsics: Intrinsics | None = None
        self.first_us: int | None = None
        self.index = -1
        self.announced: dict[str, float] = {}
        self.description = f"driving NiTE2 from {redist} (HandTracker on {device_name(device)})"

    def detect(self, gestures: bool, hands: bool) -> None:
        """NiTE detects a gesture only while someone needs it: reports, or focus for hand tracking."""
        wanted = set(NITE_GESTURES if gestures else ()) | set(self.focus if hands else ())
        wanted &= set(self.dictionary)
        for name in sorted(wanted - self.detecting):
            self.tracker.start_gesture_detection(self.types[name])
        for name in sorted(self.detecting - wanted):
            self.tracker.stop_gesture_detection(self.types[name])
        self.detecting = wanted
        self.tracking = hands
        if not hands:
            self.tracker.stop_all_hand_tracking()

    def read(self) -> SdkFrame | None:
        if 0 < self.last_frame <= self.index:
            return None  # the recording ended (NiTE would wait for a frame that never comes)
        try:
            frame = self.tracker.read_frame()
        except self.errors as error:  # the sensor went away, NiTE gave up
            raise SdkStopped(f"NiTE2 stopped delivering frames ({error!r})") from None
        try:  # copy everything out, then hand the frame back to NiTE at once
            depth = self._depth(frame)
            hands = tuple(Hand(int(h.id), hand_state(int(h.state)), nite_to_camera(h.position), Side.UNKNOWN)
                          for h in frame.hands)
            raw = [(int(g.type), nite_to_camera(g.currentPosition), int(g.state)) for g in frame.gestures]
        finally:
            frame.close()
        return SdkFrame(depth, hands, tuple(self._gestures(raw, hands, depth.timestamp)))

    def _depth(self, frame) -> DepthFrame:
        if self.intrinsics is None:
            self.intrinsics = self._intrinsics()
        video = frame.depth_frame
        pixels = np.frombuffer(video.get_buffer_as_uint16(), dtype=np.uint16)
        pixels = pixels.reshape(video.height, video.stride // 2)[:, : video.width].copy()
        self.first_us = frame.timestamp if self.first_us is None else self.first_us
        self.index = frame.frameIndex
        return DepthFrame(pixels, self.intrinsics, frame_id=frame.frameIndex,
                          timestamp=(frame.timestamp - self.first_us) / 1e6, capture_time=time.time(),
                          mirrored=self.mirrored)

    def _intrinsics(self) -> Intrinsics:
        """NiTE's own projection, measured: (0, 0, 1 m) lands on (cx, cy), (1, 1, 1 m) on (cx + fx, cy - fy)."""
        cx, cy = self.tracker.convert_hand_coordinates_to_depth(0.0, 0.0, 1000.0)
        u, v = self.tracker.convert_hand_coordinates_to_depth(1000.0, 1000.0, 1000.0)
        return Intrinsics(u - cx, cy - v, cx, cy)

    def _gestures(self, raw, hands: tuple[Hand, ...], t: float) -> list[Gesture]:
        out = []
        for kind, position, bits in raw:
            name = self.names.get(kind)
            if name is None or name not in self.detecting:
                continue
            complete = bool(bits & GESTURE_COMPLETED)
            if not complete:
                if t - self.announced.get(name, -np.inf) < IN_PROGRESS_REPEAT_S:
                    continue
                self.announced[name] = t
            else:
                self.announced.pop(name, None)
            hand = nearest(hands, position)
            hand_id = hand.id if hand is not None else 0
            if complete and name in self.focus and self.tracking and hand is None:
                new = self.tracker.start_hand_tracking(self.nite2.Point3f(*position))
                hand_id = int(getattr(new, "value", new))
            if name in self.dictionary:
                out.append(Gesture(self.dictionary[name],
                                   GestureState.COMPLETE if complete else GestureState.IN_PROGRESS,
                                   position, hand_id, Side.UNKNOWN, 1.0, t))
        return out

    def world_to_depth(self, position: Vec3) -> tuple[float, float, float]:
        u, v = self.tracker.convert_hand_coordinates_to_depth(*map(float, position))
        return (u, v, float(position[2]))

    def finish(self) -> tuple[Gesture, ...]:
        return ()  # NiTE2 completes its gestures itself

    def close(self) -> None:
        self.tracker.close()
        if self.owns_device:
            self.device.close()


def nearest(hands: tuple[Hand, ...], position: Vec3) -> Hand | None:
    """The live hand within SAME_HAND_MM of a gesture's position, if any."""
    live = [h for h in hands if h.state is not HandState.LOST]
    if not live:
        return None
    best = min(live, key=lambda h: float(np.linalg.norm(np.subtract(h.position, position))))
    return best if np.linalg.norm(np.subtract(best.position, position)) <= SAME_HAND_MM else None


def device_name(device) -> str:
    try:
        return device.get_device_info().uri.decode(errors="replace")
    except Exception:  # a recording or a driver without device info
        return "the OpenNI2 device"


class NiteBackend(SdkBackend, OpenISSNiteBackend):
    """`openiss-nite`: NiTE2's HandTracker when installed; else the open engine in NiTE mode."""

    Options = NiteOptions
    sdk_name = "NiTE2"

    @classmethod
    def sdk_missing(cls, options: NiteOptions, source: Source | None) -> str | None:
        try:
            import openni.nite2  # noqa: F401
        except ImportError:
            return "NiTE2 not used: the PyPI package `openni` (OpenNI2/NiTE2 bindings) is missing: pip install openni"
        if find_nite2(options.nite2_redist) is None:
            return f"NiTE2 runtime not found: {NITE2_HELP}"
        if find_runtime() is None:
            return f"NiTE2 not used: the OpenNI2 runtime is missing ({OPENNI2_INSTALL})"
        if options.device is None and getattr(source, "name", None) != "oni":
            return (f"NiTE2 not used: it reads an OpenNI2 device, and source {getattr(source, 'name', None)!r} "
                    f"is not one (use source 'oni', or the backend option device = \"any\")")
        return None

    def open_sdk(self) -> NiteSession:
        from openni import nite2, openni2
        from openni.utils import InitializationError, OpenNIError

        redist = find_nite2(self.options.nite2_redist)
        try:
            openni2.initialize(str(bindings_dir(find_runtime())))
            nite2.initialize(str(redist))
        except (InitializationError, OpenNIError) as error:
            raise SdkUnavailable(f"NiTE2 in {redist} cannot be loaded ({error}); reinstall its Redist folder") from None
        wanted = self.options.device
        if wanted is None:  # the `oni` source's recording
            source = self.open_source()
            return NiteSession(self, redist, source.device, False, bool(getattr(source, "mirrored", True)),
                               -1 if source.options.loop else int(getattr(source, "frames", -1)))
        try:
            device = openni2.Device.open_any() if wanted == "any" else openni2.Device(wanted.encode())
        except OpenNIError as error:
            raise SdkUnavailable(f"no OpenNI2 device {wanted!r} for NiTE2 ({error}): connect the sensor "
                                 f"or use source 'oni' with a recording") from None
        try:
            return NiteSession(self, redist, device, True, True, -1)
        except SdkUnavailable:
            device.close()
            raise
