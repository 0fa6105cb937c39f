"""A tap on the sensor path: sees every frame a backend makes, before newest-wins can drop one."""
from __future__ import annotations

from typing import Any, Callable

from host.contracts import Backend
from host.model import Frame


class SensorTap:
    """Wraps a backend for a Show. `observe(frame)` runs on the sensor thread for every frame;
    `finish()` runs once the backend has stopped. Everything else is the backend's own."""

    def __init__(self, backend: Backend, observe: Callable[[Frame], None],
                 finish: Callable[[], None] | None = None) -> None:
        self.inner = backend
        self._observe = observe
        self._finish = finish

    def __getattr__(self, name: str) -> Any:
        return getattr(self.inner, name)

    def update(self) -> Frame | None:
        frame = self.inner.update()
        if frame is not None:
            self._observe(frame)
        return frame

    def stop(self) -> None:
        try:
            self.inner.stop()
        finally:
            if self._finish is not None:
                self._finish()
