"""A backend with learned gestures: the frames it makes, plus the learned gestures in them.

The host wraps whatever backend a profile names (open engine, middleware, network, replay), so
learned gestures need nothing from the backend but its hands.
"""
from __future__ import annotations

import dataclasses
from typing import Any

from host.contracts import Backend, Update
from host.learned.recognizer import LearnedRecognizer
from host.model import Frame


class LearnedBackend:
    """Wraps a backend; `update()` returns its frame with the learned gestures appended."""

    def __init__(self, backend: Backend, recognizer: LearnedRecognizer) -> None:
        self.inner = backend
        self.recognizer = recognizer

    def __getattr__(self, name: str) -> Any:
        return getattr(self.inner, name)

    def update(self) -> Update:
        frame = self.inner.update()
        if not isinstance(frame, Frame):  # the end (None), or nothing yet (False)
            return frame
        if frame.depth is not None:
            self.recognizer.stream.flip = 1.0 if frame.depth.mirrored else -1.0
        learned = self.recognizer.update(frame.timestamp if frame.depth is not None else frame.capture_time,
                                         frame.hands)
        return dataclasses.replace(frame, gestures=frame.gestures + tuple(learned)) if learned else frame
