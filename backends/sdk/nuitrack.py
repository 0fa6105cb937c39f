"""`openiss-nuitrack` over the real Nuitrack runtime, through its official Python bindings (PyNuitrack).

PyNuitrack (`from PyNuitrack import py_nuitrack`, a wheel shipped with the Nuitrack SDK) gives
skeletons and depth: `Nuitrack()`, `init()`, `get_device_list()`, `set_device()`,
`create_modules()`, `run()`, then per frame `update()`, `get_skeleton()` (timestamp in us,
`skeletons`, each with `user_id` and joints such as `left_hand`, `right_hand`, `torso`, `head`,
each with `real` (x, y, z mm) and `confidence`) and `get_depth_data()` (uint16 mm), and
`release()`. It has no gesture API, so gestures come from our recogniser (Nuitrack mode) on
Nuitrack's hand joints, with the torso and head as the body reference.

Nuitrack drives the sensor itself, so it runs when the profile's source is a camera (which is
then left closed for Nuitrack to use); with a recorded source, or without Nuitrack, the parent
class runs: the open engine in Nuitrack mode.

What this adapter does that the thesis' OINuitrackGestureTracker did not:
- Stable hand ids from Nuitrack's user id and the side: user u's left hand is 2u - 1, the right
  2u (the thesis renumbered hands every frame), with NEW -> TRACKING -> LOST per hand
  (`lost_timeout_s`) and TOUCHING_FOV at the image border.
- Explicit sides: Nuitrack's skeleton is anatomical (`left_hand` is the performer's left).
- Every gesture has a position and the hand that made it (from the recogniser).
- Depth is copied out of Nuitrack's buffer.
- Coordinates: Nuitrack's `real` is millimetres with x towards the depth image's right, y up,
  z away: our camera frame, so `nuitrack_to_camera` passes it through unchanged, in one place.
  Whether the image is mirrored is read off the skeleton (the right shoulder on the image's
  right means mirrored), not assumed.
- Licence: an unlicensed Nuitrack stops after 3 minutes (LicenseNotAcquired). The backend says
  so once, releases Nuitrack and carries on with the open engine on the profile's source (the
  same camera, now free): the show goes on, with the engine's hand ids from then on.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from pydantic import Field

from backends.engine.backend import EngineOptions, OpenISSNuitrackBackend
from backends.sdk.adapter import SdkBackend, SdkFrame, SdkStopped, SdkUnavailable
from host import DepthFrame, Gesture, Hand, HandState, Intrinsics, Side, Source, Vec3

INSTALL = ("install Nuitrack and its PyNuitrack wheel "
           "(github.com/3DiVi/nuitrack-sdk, folder PythonNuitrack-beta), then activate a licence")
UNLICENSED_RUN_S = 180.0  # what an unlicensed Nuitrack runs for (thesis ch. 5)
NO_DEPTH_UPDATES = 90  # updates without depth (3 s at 30 Hz) before giving up on the sensor
HANDS = (("left_hand", Side.LEFT, 1), ("right_hand", Side.RIGHT, 0))  # joint, side, id = 2u - this


class NuitrackOptions(EngineOptions):
    """The open engine's options (used without Nuitrack) plus Nuitrack's sensor and joints."""

    device: str | None = Field(None, description="the serial number of the sensor Nuitrack uses; default the first")
    min_confidence: float = Field(0.3, ge=0, le=1, description="joints below this Nuitrack confidence are unseen")
    fov_deg: tuple[float, float] = Field((58.0, 45.0), description=(
        "the depth sensor's field of view (horizontal, vertical degrees): PyNuitrack does not report "
        "it; used to place hands in the depth image"))
    fov_margin: float = Field(0.02, ge=0, lt=0.5, description=(
        "a hand within this fraction of the image's size from its edge is TOUCHING_FOV"))


def nuitrack_to_camera(real) -> Vec3:
    """Nuitrack `real` (mm; x image-right, y up, z away) -> ours: the same axes, so unchanged."""
    return (float(real[0]), float(real[1]), float(real[2]))


def is_licence_error(error: BaseException) -> bool:
    """Nuitrack's LicenseNotAcquiredException, however the bindings surface it (type or message)."""
    return "licensenotacquired" in f"{type(error).__name__} {error}".replace(" ", "").lower()


@dataclass
class _Seen:
    """What is known of one hand between frames."""

    hand: Hand  # as last seen
    last_seen: float


class NuitrackSession:
    """One running Nuitrack: skeleton hands with stable ids and states, our gestures, owned depth."""

    def __init__(self, backend: "NuitrackBackend") -> None:
        from PyNuitrack import py_nuitrack

        options: NuitrackOptions = backend.options
        self.options = options
        self.nuitrack = py_nuitrack.Nuitrack()
        try:
            self.nuitrack.init()
        except Exception as error:  # the bindings raise their own types; any failure means no Nuitrack
            raise SdkUnavailable(f"Nuitrack cannot start ({error}): check its installation ({INSTALL})") from None
        try:
            device = self._device(self.nuitrack.get_device_list())
            self.nuitrack.set_device(device)
            self.nuitrack.create_modules()
            self.nuitrack.run()
        except SdkUnavailable:
            self.nuitrack.release()
            raise
        except Exception as error:
            self.nuitrack.release()
            what = "its licence is not valid" if is_licence_error(error) else str(error)
            raise SdkUnavailable(f"Nuitrack cannot run on {device.get_name()}: {what} ({INSTALL})") from None
        self.description = f"driving Nuitrack {self.nuitrack.get_version()} on {device.get_name()} " \
                           f"(serial {device.get_serial_number()}); gestures from the open recogniser"
        self.recognizer = backend.recognizer(options)
        self.seen: dict[int, _Seen] = {}
        self.intrinsics: Intrinsics | None = None
        self.mirrored = True
        self.first_us: int | None = None
        self.started = time.monotonic()
        self.index = 0

    def _device(self, devices):
        if not devices:
            raise SdkUnavailable("Nuitrack found no depth sensor: connect one (or use a recorded source)")
        wanted = self.options.device
        for device in devices:
            if wanted is None or device.get_serial_number() == wanted:
                return device
        found = ", ".join(f"{d.get_name()} {d.get_serial_number()}" for d in devices)
        raise SdkUnavailable(f"Nuitrack has no sensor with serial {wanted!r} (connected: {found})")

    def detect(self, gestures: bool, hands: bool) -> None:
        """Nuitrack always tracks skeletons; what is reported is the backend's choice."""

    def read(self) -> SdkFrame | None:
        skeletons, depth = self._update()
        t = (skeletons.timestamp - self.first_us) / 1e6
        for skeleton in skeletons.skeletons:
            self._mirroring(skeleton)
        depth_frame = self._depth(depth, t)
        hands, body = self._hands(skeletons.skeletons, t, depth_frame)
        gestures = self.recognizer.update(t, hands, body, self.mirrored)
        return SdkFrame(depth_frame, tuple(hands), tuple(gestures))

    def _update(self):
        for _ in range(NO_DEPTH_UPDATES):
            try:
                self.nuitrack.update()
                skeletons = self.nuitrack.get_skeleton()
                depth = self.nuitrack.get_depth_data()
            except Exception as error:
                ran = time.monotonic() - self.started
                if is_licence_error(error):
                    raise SdkStopped(f"Nuitrack stopped after {ran:.0f} s: no licence (LicenseNotAcquired; an "
                                     f"unlicensed Nuitrack runs {UNLICENSED_RUN_S / 60:.0f} minutes). "
                                     f"Activate a licence for the whole show") from None
                raise SdkStopped(f"Nuitrack stopped after {ran:.0f} s: {error}") from None
            if depth is not None and depth.size:
                self.first_us = skeletons.timestamp if self.first_us is None else self.first_us
                return skeletons, depth
        raise SdkStopped(f"Nuitrack delivered no depth in {NO_DEPTH_UPDATES} updates: is the sensor still connected?")

    def _depth(self, depth: np.ndarray, t: float) -> DepthFrame:
        pixels = np.array(depth, dtype=np.uint16, copy=True)  # owned: Nuitrack reuses its buffer
        if self.intrinsics is None:
            h, w = pixels.shape
            self.intrinsics = Intrinsics.from_fov(w, h, *self.options.fov_deg)
        self.index += 1
        return DepthFrame(pixels, self.intrinsics, frame_id=self.index, timestamp=t,
                          capture_time=time.time(), mirrored=self.mirrored)

    def _joint(self, skeleton, name: str) -> Vec3 | None:
        joint = getattr(skeleton, name)
        if float(joint.confidence) < self.options.min_confidence:
            return None
        return nuitrack_to_camera(joint.real)

    def _hands(self, skeletons, t: float, depth: DepthFrame) -> tuple[list[Hand], dict[str, Vec3]]:
        hands, body, now = [], {}, set()
        for skeleton in skeletons:
            user = int(skeleton.user_id)
            for name in ("torso", "head"):
                if name not in body and (p := self._joint(skeleton, name)) is not None:
                    body[name] = p
            for joint, side, minus in HANDS:
                position = self._joint(skeleton, joint)
                if position is None:
                    continue
                hid = 2 * user - minus
                now.add(hid)
                state = HandState.TRACKING if hid in self.seen else HandState.NEW
                if state is HandState.TRACKING and self._at_border(position, depth):
                    state = HandState.TOUCHING_FOV
                hand = Hand(hid, state, position, side, user, float(getattr(skeleton, joint).confidence))
                self.seen[hid] = _Seen(hand, t)
                hands.append(hand)
        for hid, seen in list(self.seen.items()):  # unseen hands are left out, then LOST once
            if hid not in now and t - seen.last_seen > self.options.lost_timeout_s:
                del self.seen[hid]  # seen again later, it is NEW (with the same id)
                hands.append(Hand(hid, HandState.LOST, seen.hand.position, seen.hand.side, seen.hand.user_id, 0.0))
        return hands, body

    def _mirroring(self, skeleton) -> None:
        """Mirrored when the performer's right shoulder is on the image's right (larger x)."""
        left, right = self._joint(skeleton, "left_shoulder"), self._joint(skeleton, "right_shoulder")
        if left is not None and right is not None and abs(right[0] - left[0]) > 1.0:
            self.mirrored = right[0] > left[0]

    def _at_border(self, position: Vec3, depth: DepthFrame) -> bool:
        u, v, _ = depth.world_to_depth(position)
        mx, my = self.options.fov_margin * depth.width, self.options.fov_margin * depth.height
        return not (mx <= u <= depth.width - 1 - mx and my <= v <= depth.height - 1 - my)

    def world_to_depth(self, position: Vec3) -> tuple[float, float, float]:
        if self.intrinsics is None:
            raise SdkStopped("Nuitrack has delivered no depth frame yet")
        return self.intrinsics.world_to_depth(*position)

    def finish(self) -> tuple[Gesture, ...]:
        return tuple(self.recognizer.finish())  # our recogniser on Nuitrack's joints

    def close(self) -> None:
        self.nuitrack.release()


def is_camera(source: Source | None) -> bool:
    """A live source that is not a file: Nuitrack can open the same sensor itself."""
    return source is None or (source.live and getattr(source.options, "path", None) is None)


class NuitrackBackend(SdkBackend, OpenISSNuitrackBackend):
    """`openiss-nuitrack`: Nuitrack's skeletons + our recogniser; else the open engine in Nuitrack mode."""

    Options = NuitrackOptions
    sdk_name = "Nuitrack"

    @classmethod
    def sdk_missing(cls, options: NuitrackOptions, source: Source | None) -> str | None:
        try:
            from PyNuitrack import py_nuitrack  # noqa: F401
        except ImportError:
            return f"Nuitrack runtime not found (its Python bindings PyNuitrack are missing: {INSTALL})"
        if not is_camera(source):
            return (f"Nuitrack not used: it reads its own sensor, and source {source.name!r} is a recording "
                    f"(use a camera source)")
        return None

    def open_sdk(self) -> NuitrackSession:
        return NuitrackSession(self)
