"""What the NiTE2 and Nuitrack backends share: choose the SDK or the open engine, fall back cleanly.

An SDK session owns its sensor and hands over whole frames (depth, hands, gestures), so in SDK
mode `update()` asks the session instead of reading the source. Whenever the SDK cannot run
(runtime missing, no device, a licence that runs out mid-show), the backend runs the open
engine of its parent class on the profile's source, says so once, and the show goes on.
"""
from __future__ import annotations

import sys
from dataclasses import dataclass
from typing import ClassVar, Protocol

from pydantic import BaseModel

from backends.engine.backend import EngineBackend, announce_once
from host import Backend, DepthFrame, Frame, Gesture, Hand, Source, Vec3, profile_source


class SdkUnavailable(RuntimeError):
    """The SDK cannot run here; the message says what is missing and how to get it."""


class SdkStopped(RuntimeError):
    """The SDK stopped delivering mid-show (e.g. Nuitrack's licence ran out)."""


@dataclass(frozen=True)
class SdkFrame:
    """One SDK frame in our model: an owned depth copy, hands and gestures (all gestures seen)."""

    depth: DepthFrame
    hands: tuple[Hand, ...]
    gestures: tuple[Gesture, ...]


class SdkSession(Protocol):
    """An open middleware session (one per backend)."""

    description: str  # what runs, for the one-line announcement

    def detect(self, gestures: bool, hands: bool) -> None:
        """Start or stop the middleware's gesture detection and hand tracking to match."""

    def read(self) -> SdkFrame | None:
        """The next frame; None at the end of a recording; SdkStopped if the SDK gave up."""

    def world_to_depth(self, position: Vec3) -> tuple[float, float, float]:
        """The middleware's own mm -> (u, v, z) conversion (convertHandCoordinatesToDepth)."""

    def finish(self) -> tuple[Gesture, ...]:
        """The frames ended: gestures still waiting to be confirmed complete (none where the
        middleware keeps its own gesture state)."""

    def close(self) -> None:
        """Release the middleware's trackers and the device it opened."""


@dataclass(frozen=True)
class Implementation:
    """Which implementation a backend will run here, and why (for `note` and for people)."""

    sdk: bool
    why: str


class SdkBackend(EngineBackend):
    """An EngineBackend mode whose `open_sdk()` may supply the frames instead of the open engine."""

    #: the middleware's name in messages ("NiTE2")
    sdk_name: ClassVar[str] = ""
    #: what runs instead ("the open engine in NiTE mode (...)"): the engine mode's own, which the
    #: adapter also derives from (so no default here, where it would shadow the mode's)
    engine_mode: ClassVar[str]

    @classmethod
    def sdk_missing(cls, options: BaseModel, source: Source | None) -> str | None:
        """Why the SDK cannot run with these options on this source (None: it can try)."""
        raise NotImplementedError

    @classmethod
    def implementation(cls, options: BaseModel | None = None, source: Source | None = None) -> Implementation:
        """Which implementation `init()` will try, without opening anything."""
        reason = cls.sdk_missing(options if options is not None else cls.Options(), profile_source(source))
        return Implementation(False, reason) if reason else Implementation(True, f"{cls.sdk_name} runtime found")

    @property
    def runs_sdk(self) -> bool:
        """True while the middleware itself supplies the frames (False: the open engine)."""
        return getattr(self, "_sdk", None) is not None

    def finish(self) -> tuple[Gesture, ...]:
        """The frames ended: what their supplier still had pending. That is the middleware's
        session while it runs, or when it stopped with no source to fall back to; otherwise the
        open engine's."""
        if self._sdk is None and self._ended is None:
            return super().finish()
        pending = self._sdk.finish() if self._sdk is not None else self._ended
        return pending if self.detecting_gestures else ()

    def open_sdk(self) -> SdkSession:
        """Open the middleware on its sensor; SdkUnavailable says why it cannot."""
        raise NotImplementedError

    def init(self) -> None:
        self._sdk: SdkSession | None = None
        self._ended: tuple[Gesture, ...] | None = None  # pending when the SDK stopped and the show ended
        self._source_opened = False
        self._seq = 0
        plan = self.implementation(self.options, self.source)
        reason = plan.why
        if plan.sdk:
            try:
                self._sdk = self.open_sdk()
            except SdkUnavailable as error:
                reason = str(error)
        if self._sdk is None:
            self._run_engine(reason)
            return
        announce_once(self.name, self._sdk.description)
        self._sync()

    def _run_engine(self, reason: str) -> None:
        """The parent's open engine on the profile's source, opened afresh (sequence numbers carry on)."""
        self._close_sdk()
        if self._source_opened:  # the SDK read through it (NiTE on an .oni file)
            self.source.close()
        seq = self._seq
        self.note = f"{reason}; running {self.engine_mode}"
        super().init()
        self._source_opened, self._seq = True, seq

    def open_source(self) -> Source:
        """Open the profile's source for an SDK that reads through it (NiTE on an .oni file)."""
        if self.source is None:
            raise SdkUnavailable(f"backend {self.name!r} has no source to open")
        Backend.init(self)
        self._source_opened = True
        return profile_source(self.source)

    def _sync(self) -> None:
        if self._sdk is not None:
            self._sdk.detect(self.detecting_gestures, self.tracking_hands)

    def start_gesture_detection(self) -> None:
        super().start_gesture_detection()
        self._sync()

    def stop_gesture_detection(self) -> None:
        super().stop_gesture_detection()
        self._sync()

    def start_hand_tracking(self) -> None:
        super().start_hand_tracking()
        self._sync()

    def stop_hand_tracking(self) -> None:
        super().stop_hand_tracking()
        self._sync()

    def update(self) -> Frame | None:
        if self._sdk is None:
            return super().update()
        try:
            got = self._sdk.read()
        except SdkStopped as error:  # said once: this backend's SDK is gone for the rest of the show
            if self.source is None:
                print(f"issv: {self.name}: {error}; no source to fall back to: the show ends", file=sys.stderr)
                self._ended = self._sdk.finish()
                self._close_sdk()
                return None
            print(f"issv: {self.name}: {error}; switching to {self.engine_mode} on the profile's source",
                  file=sys.stderr)
            self._run_engine(str(error))
            return super().update()
        if got is None:
            return None
        self._seq += 1
        return Frame(self._seq, got.depth.capture_time, got.depth, got.hands if self.tracking_hands else (),
                     got.gestures if self.detecting_gestures else (), self.name)

    def _close_sdk(self) -> None:
        sdk, self._sdk = self._sdk, None
        if sdk is not None:
            sdk.close()

    def stop(self) -> None:
        self._close_sdk()
        self.detecting_gestures = self.tracking_hands = False
        if self.source is not None and self._source_opened:
            self.source.close()
            self._source_opened = False

    def world_to_depth(self, position: Vec3) -> tuple[float, float, float]:
        if self._sdk is not None:
            return self._sdk.world_to_depth(position)
        return super().world_to_depth(position)
