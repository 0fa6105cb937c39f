"""Learned gestures per user, on the backends that report users (the open engine, osc-in, mediapipe).

The host recognises learned gestures after the backend, on its hands (host/learned/backend.py).
A backend that reports users (`Frame.users`) may carry several performers: each gets a learned
recogniser of its own, fed its own hands and its torso and head (as `issv gestures --learned`
feeds a file's), so two performers' motions never mix, and its events carry its user id, as the
built-in recogniser's do. Frames without users go to the single recogniser on every hand
(LearnedBackend), unchanged.
"""
from __future__ import annotations

import dataclasses
from typing import Any

from host.contracts import Backend, Update
from host.learned.backend import LearnedBackend
from host.learned.features import body_of
from host.learned.recognizer import LearnedRecognizer
from host.model import Frame, Gesture, HandState, User


class _Given:
    """The frame LearnedByUser already read, for LearnedBackend to take as its backend's."""

    frame: Update = None

    def update(self) -> Update:
        return self.frame


class LearnedByUser:
    """Wraps a backend; `update()` returns its frame with each user's learned gestures appended."""

    def __init__(self, backend: Backend, gestures: list[Any]) -> None:
        self.inner = backend
        self._recognizers: dict[int, LearnedRecognizer] = {}  # private names: the rest is the backend's
        self._frame = _Given()
        self._first = LearnedRecognizer(gestures)  # built once: each user's is a fresh copy
        self._anyone = LearnedBackend(self._frame, self._first)  # frames without users

    def __getattr__(self, name: str) -> Any:
        return getattr(self.inner, name)

    def update(self) -> Update:
        frame = self.inner.update()
        if not isinstance(frame, Frame) or not frame.users:
            self._frame.frame = frame
            return self._anyone.update()
        learned: list[Gesture] = []
        for user in frame.users:
            learned += self._user(frame, user)
        return dataclasses.replace(frame, gestures=frame.gestures + tuple(learned)) if learned else frame

    def _user(self, frame: Frame, user: User) -> list[Gesture]:
        if user.state is HandState.LOST:
            self._recognizers.pop(user.id, None)
            return []
        mirrored = frame.depth.mirrored if frame.depth is not None else True
        recognizer = self._recognizers.get(user.id)
        if recognizer is None:
            recognizer = self._recognizers[user.id] = self._first.fresh(mirrored)
        t = frame.timestamp if frame.depth is not None else frame.capture_time
        hands = [h for h in frame.hands if h.user_id == user.id]
        return [dataclasses.replace(g, user_id=user.id) for g in recognizer.update(t, hands, body_of(user))]
