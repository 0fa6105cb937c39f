"""Learned gestures on any hand stream: frames in, ordinary gesture events out.

Runs in the host after the backend (track, gestures, the show), so every backend's hands (the
open engine, the middleware modes, network, replay) get the learned gestures without a change.
Events are GestureType.LEARNED with the gesture's name as `label`: `"name": NAME` and
`"native": "learned"` in event lines, OSC and recordings.
"""
from __future__ import annotations

import copy
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np

from host.learned.classifier import Classifier
from host.learned.features import PostureStream
from host.learned.gesture_file import LearnedGesture, load
from host.learned.matcher import Matcher
from host.model import Gesture, GestureState, GestureType, Hand, Side


class LearnedRecognizer:
    """`update(t, hands, body) -> list[Gesture]` per frame, like a backend's recogniser."""

    def __init__(self, gestures: list[LearnedGesture], mirrored: bool = True,
                 thresholds: Mapping[str, float] | None = None, classifier: Classifier | None = None) -> None:
        overrides = thresholds or {}
        self.matcher = Matcher(gestures, [overrides.get(g.name, g.threshold) for g in gestures],
                               classifier=classifier)
        self.stream = PostureStream(mirrored)
        self._hands: tuple[Hand, ...] = ()

    def fresh(self, mirrored: bool = True) -> "LearnedRecognizer":
        """A recogniser of the same gestures for another performer, ready at once (`Matcher.fresh`)."""
        other = copy.copy(self)
        other.matcher = self.matcher.fresh()
        other.stream = PostureStream(mirrored)
        other._hands = ()
        return other

    @classmethod
    def from_files(cls, paths: Sequence[Path | str], mirrored: bool = True,
                   thresholds: Mapping[str, float] | None = None) -> "LearnedRecognizer":
        return cls([load(p) for p in paths], mirrored, thresholds)

    def update(self, t: float, hands: Sequence[Hand], body: Mapping[str, Sequence[float]] | None = None,
               ) -> list[Gesture]:
        postures = self.stream.update(t, hands, body or {})
        if self.stream.broken:
            self.matcher.reset()
            return []
        self._hands = tuple(h for h in hands if h.in_view) or self._hands
        events = []
        for posture in postures:
            for match in self.matcher.update(posture.vector):
                events.append(self._event(self.matcher.forms[match.form], match.ratio, t, match.complete))
        return events

    def _event(self, gesture: LearnedGesture, ratio: float, t: float, complete: bool) -> Gesture:
        """IN_PROGRESS or COMPLETE at the hand(s) making it (a two-handed gesture rolled with one arm
        alone: at that arm, matcher.py's `forms`); confidence 0.5 at the threshold, 1 at a perfect match."""
        used = [h for h in self._hands if gesture.hands == "both" or h.side.value == gesture.hands] or list(
            self._hands)
        position = tuple(np.mean([h.position for h in used], axis=0)) if used else (0.0, 0.0, 0.0)
        both = gesture.hands == "both" and len(used) > 1
        hand = used[0] if used and not both else None
        state = GestureState.COMPLETE if complete else GestureState.IN_PROGRESS
        return Gesture(GestureType.LEARNED, state, position,
                       hand.id if hand else 0, hand.side if hand else Side.UNKNOWN,
                       0.5 + 0.5 * float(np.clip(1.0 - ratio, 0.0, 1.0)), t, label=gesture.name,
                       hands=tuple(h.id for h in used) if both else ())
