"""A tap on the sensor path: sees every frame a backend makes, before newest-wins can drop one."""
from __future__ import annotations

from typing import Any, Callable

from host.contracts import Backend, Update
from host.model import Frame, Gesture


class SensorTap:
    """Wraps a backend for a Show. `observe(frame)` runs on the sensor thread for every frame;
    `observe_end(gestures)` gets what the backend's `finish()` completed when its source ended;
    `closed()` runs once the backend has stopped. Everything else is the backend's own."""

    def __init__(self, backend: Backend, observe: Callable[[Frame], None],
                 closed: Callable[[], None] | None = None,
                 observe_end: Callable[[tuple[Gesture, ...]], None] | None = None) -> None:
        self.inner = backend
        self._observe = observe
        self._closed = closed
        self._observe_end = observe_end

    def __getattr__(self, name: str) -> Any:
        return getattr(self.inner, name)

    def update(self) -> Update:
        frame = self.inner.update()
        if isinstance(frame, Frame):
            self._observe(frame)
        return frame

    def finish(self) -> tuple[Gesture, ...]:
        gestures = self.inner.finish()
        if gestures and self._observe_end is not None:
            self._observe_end(gestures)
        return gestures

    def stop(self) -> None:
        try:
            self.inner.stop()
        finally:
            if self._closed is not None:
                self._closed()
