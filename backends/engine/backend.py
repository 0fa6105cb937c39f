"""The open engine as backends: depth -> HandTracker -> GestureRecognizer -> Frame.

One class does the work; the named backends differ only in their dictionary (which gestures,
under which native names), whether hands wait for a focus gesture, and the sensor geometry they
present. `build_engine()` is the seam where an SDK adapter (NiTE2, Nuitrack) replaces the open
engine when its runtime is installed.
"""
from __future__ import annotations

import sys
from typing import ClassVar, Mapping

import numpy as np
from pydantic import Field

from backends.engine.geometry import KINECT_V1, to_geometry
from backends.engine.recognizer import NITE_DICTIONARY, NUITRACK_DICTIONARY, GestureRecognizer
from backends.engine.rules import GestureRules
from backends.engine.sides import nuitrack_id, renamed_gesture, renamed_hand
from backends.engine.tracker import HandTracker, TrackerOptions, TrackResult
from backends.users import hand_id
from host import Backend, DepthFrame, Frame, Gesture, GestureState, GestureType, Hand, HandState


class EngineOptions(TrackerOptions):
    """The tracker's options (mm, s) plus `gestures`: overrides of any GestureRules threshold."""

    gestures: GestureRules = Field(default_factory=GestureRules,
                                   description="gesture thresholds (mm, s), e.g. {swipe_min_travel_mm = 300}")


class Engine:
    """Tracker and recogniser for one stream of depth frames."""

    def __init__(self, options: EngineOptions, dictionary: Mapping[str, GestureType] | None) -> None:
        self.tracker = HandTracker(options)
        self.recognizer = GestureRecognizer(options.gestures, dictionary)
        self.last: TrackResult | None = None

    def step(self, depth: DepthFrame) -> tuple[TrackResult, list[Gesture]]:
        result = self.tracker.process(depth)
        self.last = result
        # A hand held where it was last seen (a dropout of a frame or two) is no measurement: its
        # standing still would read as a stop. The recogniser gets the hands found in this frame.
        measured = [h for h in result.hands if h.id in result.seen or not h.in_view]
        gestures = self.recognizer.update(depth.timestamp, measured, result.body, depth.mirrored)
        return result, gestures


_announced: set[str] = set()


def announce_once(backend: str, message: str) -> None:
    """Say once per process which implementation a backend runs (SDK or open engine)."""
    if backend not in _announced:
        _announced.add(backend)
        print(f"issv: {backend}: {message}", file=sys.stderr)


class EngineBackend(Backend):
    """Hands and gestures from depth with the open engine. Subclasses set the mode."""

    Options = EngineOptions
    #: canonical gesture name -> native type; None = every gesture under its first native name.
    dictionary: ClassVar[Mapping[str, GestureType] | None] = None
    #: gestures that start hand tracking (NiTE's focus gestures); empty = hands as soon as seen.
    focus_gestures: ClassVar[frozenset[str]] = frozenset()
    #: the sensor geometry frames are presented in ((width, height), Intrinsics); None = the source's own.
    geometry: ClassVar[tuple | None] = None
    #: what the backend says about itself when it starts (None: nothing to say).
    note: ClassVar[str | None] = None
    #: Nuitrack's hand ids (left 1, right 2) rather than the engine's (10 * user + 1 or + 2).
    nuitrack_ids: ClassVar[bool] = False

    @classmethod
    def recognizer(cls, options: EngineOptions | None = None) -> GestureRecognizer:
        """The mode's recogniser alone, for hand trajectories (`issv gestures`)."""
        options = options if options is not None else cls.Options()
        return GestureRecognizer(options.gestures, cls.dictionary)

    def build_engine(self) -> Engine:
        """What turns depth into hands and gestures; an SDK adapter overrides this."""
        return Engine(self.options, self.dictionary)

    def init(self) -> None:
        super().init()
        if self.note:
            announce_once(self.name, self.note)
        self.engine = self.build_engine()
        self._seq = 0
        self._focused: set[int] = set()
        self._shown: set[int] = set()
        self._ids = nuitrack_id if self.nuitrack_ids else hand_id

    def update(self) -> Frame | None:
        depth = self.source.read()
        if depth is None:
            return None
        if self.geometry is not None:
            depth = to_geometry(depth, *self.geometry)
        result, gestures = self.engine.step(depth)
        gestures = self._named(gestures)
        hands: tuple[Hand, ...] = ()
        if self.tracking_hands:  # both of the user's hands (skeleton.py), resting ones included
            hands = self._reported_hands(tuple(renamed_hand(h, self._ids) for h in result.user_hands), gestures)
        self._seq += 1
        return Frame(self._seq, depth.capture_time, depth, hands,
                     tuple(gestures) if self.detecting_gestures else (), self.name,
                     make_user_mask=lambda: result.full_mask(depth))

    def finish(self) -> tuple[Gesture, ...]:
        """The source ended: the recogniser's swipes still waiting to be confirmed complete."""
        if not self.detecting_gestures:
            return ()
        return self._named(self.engine.recognizer.finish())

    def _named(self, gestures: list[Gesture]) -> tuple[Gesture, ...]:
        """The gestures, naming their hands as the reported hands are named (by side)."""
        return tuple(renamed_gesture(g, self._ids) for g in gestures)

    def _reported_hands(self, hands: tuple[Hand, ...], gestures: tuple[Gesture, ...]) -> tuple[Hand, ...]:
        """All hands, or (focus mode) only those that made a focus gesture, NEW from that frame on
        and kept while the user is in view (a focused hand dropping to rest is not lost)."""
        if not self.focus_gestures:
            return hands
        for g in gestures:
            if g.state is GestureState.COMPLETE and g.name in self.focus_gestures:
                hand = self._hand_at(hands, g)
                if hand is not None:
                    self._focused.add(hand.id)
        out = []
        for h in hands:
            if h.id not in self._focused:
                continue
            if not h.in_view:
                self._focused.discard(h.id)
                self._shown.discard(h.id)
            elif h.id not in self._shown:
                self._shown.add(h.id)
                h = Hand(h.id, HandState.NEW, h.position, h.side, h.user_id, h.confidence)
            out.append(h)
        return tuple(out)

    @staticmethod
    def _hand_at(hands: tuple[Hand, ...], g: Gesture) -> Hand | None:
        """The hand that made the gesture: by id, else the one nearest where it happened."""
        live = [h for h in hands if h.in_view]
        for h in live:
            if h.id == g.hand_id:
                return h
        if not live:
            return None
        return min(live, key=lambda h: float(np.linalg.norm(np.subtract(h.position, g.position))))


class OpenISSBackend(EngineBackend):
    """`openiss`, the default: the union dictionary, confidences, which hand did it."""

    name = "openiss"


class SimpleOpenNIBackend(EngineBackend):
    """`simpleopenni`: the legacy ISSv2 backend's behaviour (NiTE 1 through SimpleOpenNI).

    NiTE's three gestures; hands only after a focus gesture (wave or click), from that hand;
    frames presented as a Kinect v1 sees them: 640x480, 57x43 degrees (other sensors resampled).
    """

    name = "simpleopenni"
    dictionary = NITE_DICTIONARY
    focus_gestures = frozenset({"wave", "click"})
    geometry = KINECT_V1


class OpenISSNiteBackend(EngineBackend):
    """`openiss-nite`: the OpenISS NiTE2 adapter; without a NiTE2 runtime, the open engine in NiTE mode."""

    name = "openiss-nite"
    dictionary = NITE_DICTIONARY
    focus_gestures = frozenset({"wave", "click"})
    #: what runs in place of the middleware (the SDK adapter says it too when it falls back)
    engine_mode = "the open engine in NiTE mode (wave, click, hand_raise; focus gestures)"
    note = f"NiTE2 runtime not used: running {engine_mode}"


class OpenISSNuitrackBackend(EngineBackend):
    """`openiss-nuitrack`: the OpenISS Nuitrack adapter; without Nuitrack, the open engine in Nuitrack mode."""

    name = "openiss-nuitrack"
    dictionary = NUITRACK_DICTIONARY
    nuitrack_ids = True
    #: what runs in place of the middleware (the SDK adapter says it too when it falls back)
    engine_mode = ("the open engine in Nuitrack mode (six gestures; a left and a right hand while a user is "
                   "in view, resting ones where the depth shows them hang)")
    note = f"Nuitrack runtime not used: running {engine_mode}"
