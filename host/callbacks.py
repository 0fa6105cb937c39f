"""SimpleOpenNI-style callbacks, for porting ISSv2 Processing sketches with few changes.

ISSv2 sketches reacted to SimpleOpenNI's callbacks (onNewHand, onTrackedHand, onLostHand,
onCompletedGesture, and the older onCreateHands / onUpdateHands / onDestroyHands /
onRecognizeGesture of SimpleOpenNI 0.27). `SimpleOpenNIEffect` turns the host's frames and gesture
events into those calls, so a sketch's callback bodies move over almost line by line. Unlike
SimpleOpenNI, no focus gesture and no `startTrackingHands` call are needed: every backend's hands
arrive as they are tracked.
"""
from __future__ import annotations

from host.contracts import Effect, Stage
from host.model import Frame, Gesture, GestureState, GestureType, Vec3


class SimpleOpenNIEffect(Effect):
    """An effect whose hooks are SimpleOpenNI's callbacks. Override the ones the sketch used.

    Hands: the first frame a hand id appears in -> `on_new_hand` (and `on_create_hands`); every
    later frame it is present in -> `on_tracked_hand` (`on_update_hands`); the first frame it is
    gone or LOST -> `on_lost_hand` (`on_destroy_hands`). Positions are millimetres (x right, y up,
    z away from the camera), times are source seconds.

    Gestures: each completed gesture -> `on_completed_gesture(gesture_type, pos)` and
    `on_recognize_gesture(name, id_position, end_position)`. The type is normalised to the first
    dictionary entry with the same meaning (PUSH -> CLICK, WAVING -> WAVE), so a sketch that tests
    `gesture_type == self.GESTURE_WAVE` works on every backend. A subclass that overrides
    `on_frame` or `on_gesture` must call `super()` to keep the callbacks coming.
    """

    GESTURE_WAVE = GestureType.WAVE
    GESTURE_CLICK = GestureType.CLICK
    GESTURE_HAND_RAISE = GestureType.HAND_RAISE

    def setup(self, stage: Stage) -> None:
        super().setup(stage)
        self._hands: dict[int, Vec3] = {}
        self._started: dict[tuple[int, str], Vec3] = {}  # (hand, gesture) -> where it began

    # -- what the host calls -------------------------------------------------------------------
    def on_frame(self, frame: Frame) -> None:
        t = frame.timestamp
        present = {h.id: h.position for h in frame.hands if h.in_view}
        for hand_id, pos in present.items():
            if hand_id in self._hands:
                self.on_tracked_hand(hand_id, pos)
                self.on_update_hands(hand_id, pos, t)
            else:
                self.on_new_hand(hand_id, pos)
                self.on_create_hands(hand_id, pos, t)
        for hand_id in sorted(self._hands.keys() - present.keys()):
            self.on_lost_hand(hand_id)
            self.on_destroy_hands(hand_id, t)
        self._hands = present

    def on_gesture(self, gesture: Gesture) -> None:
        key = (gesture.hand_id, gesture.name)
        if gesture.state is GestureState.IN_PROGRESS:
            self._started[key] = gesture.position
            return
        start = self._started.pop(key, gesture.position)
        self.on_completed_gesture(GestureType.from_canonical(gesture.name), gesture.position)
        self.on_recognize_gesture(gesture.name, start, gesture.position)

    # -- SimpleOpenNI 1.96 callbacks -----------------------------------------------------------
    def on_new_hand(self, hand_id: int, pos: Vec3) -> None:
        """A hand is tracked for the first time (onNewHand)."""

    def on_tracked_hand(self, hand_id: int, pos: Vec3) -> None:
        """A tracked hand has a new position (onTrackedHand)."""

    def on_lost_hand(self, hand_id: int) -> None:
        """A hand is no longer tracked (onLostHand)."""

    def on_completed_gesture(self, gesture_type: GestureType, pos: Vec3) -> None:
        """A gesture was completed at `pos` (onCompletedGesture)."""

    # -- SimpleOpenNI 0.27 callbacks -----------------------------------------------------------
    def on_create_hands(self, hand_id: int, pos: Vec3, time: float) -> None:
        """onCreateHands: as on_new_hand, with the time in source seconds."""

    def on_update_hands(self, hand_id: int, pos: Vec3, time: float) -> None:
        """onUpdateHands: as on_tracked_hand, with the time in source seconds."""

    def on_destroy_hands(self, hand_id: int, time: float) -> None:
        """onDestroyHands: as on_lost_hand, with the time in source seconds."""

    def on_recognize_gesture(self, name: str, id_position: Vec3, end_position: Vec3) -> None:
        """onRecognizeGesture: the canonical name, where the gesture began and where it ended."""
