"""What every camera source shares: the device's own rate and drops, and surviving an unplug.

A subclass opens its device in `connect()`, releases it in `disconnect()` and waits for the next
image in `grab()`; a colour camera also says how its frames are made (`frame`, `blank`). When no
image comes for `STALL_S` seconds (or `grab()` gives up sooner) the camera is taken as gone: that
is said once on stderr (`stalled()` says why), the show goes on with the last frame (re-sent at the
camera's rate), and the device is reopened every `RETRY_S` seconds until an image comes again, which
is said once too. A device that reopens but fails again before any image, for the same reason (a
camera whose every frame is undecodable), is not said again each second.
"""
from __future__ import annotations

import sys
import time
from collections import deque
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from host import ColourFrame, DepthFrame, Source
from host.errors import UserError


class EndOfStream(Exception):
    """A replayed device (a .bag, a fakenect dump) has played its last frame."""


@dataclass(frozen=True)
class Grabbed:
    """One image from the device (depth: millimetres), the device's clock (s), frames it skipped,
    and when (time.perf_counter()) the library handed it over."""

    image: np.ndarray
    device_time: float
    skipped: int = 0
    received: float = field(default_factory=time.perf_counter)


class LiveCamera(Source):
    """A camera (or a library replaying one at its own pace): depth unless a subclass makes other frames."""

    live: ClassVar[bool] = True
    STALL_S: ClassVar[float] = 2.0
    RETRY_S: ClassVar[float] = 1.0
    mirrored: ClassVar[bool] = False  # cameras send their own view
    width: int
    height: int  # connect() sets these, the intrinsics and fps

    def connect(self) -> None:
        raise NotImplementedError

    def disconnect(self) -> None:
        pass

    def grab(self, timeout: float) -> Grabbed | None:
        """The next image, None after `timeout` seconds without one (or sooner, when the device is known
        to be lost); EndOfStream on a replay's end."""
        raise NotImplementedError

    def stalled(self) -> str:
        """Why no image came, said once as the camera is taken as gone."""
        return f"no {type(self).frames} frame for {self.STALL_S:g} s (unplugged?)"

    def frame(self, image: np.ndarray, frame_id: int, timestamp: float) -> DepthFrame:
        """The frame the show gets for one image."""
        return DepthFrame(image, self.intrinsics, frame_id=frame_id, timestamp=timestamp, mirrored=self.mirrored)

    def blank(self) -> np.ndarray:
        """What is shown when the camera is lost before it sent anything: no reading."""
        return np.zeros((self.height, self.width), np.uint16)

    def open(self) -> None:
        self._arrivals: deque[float] = deque(maxlen=90)
        self.dropped = 0
        self._last: DepthFrame | ColourFrame | None = None  # the last frame made, and its image
        self._last_image: np.ndarray | None = None
        self._lost_at: float | None = None  # lost since; until an image comes, even once reopened
        self._reopened = False  # connect() answered since the loss, no image yet
        self._why = ""  # what the loss was said to be
        self._retry_at = 0.0
        self._count = 0
        self._first_time: float | None = None
        self._base = 0.0  # source time where the device's clock starts (it may restart on a replug)
        self.handover_s = 0.0
        self.connect()

    def close(self) -> None:
        self.disconnect()

    @property
    def rate(self) -> float:
        """Frames per second the device delivered over the last few seconds (0 while lost)."""
        a = self._arrivals
        if self._lost_at is not None or len(a) < 2 or a[-1] == a[0]:
            return 0.0
        return (len(a) - 1) / (a[-1] - a[0])

    def health(self) -> str:
        """One line for the HUD: the device's own rate, frames it dropped, and whether it is there."""
        state = "" if self._lost_at is None else f"  LOST {time.monotonic() - self._lost_at:.0f} s"
        return f"{self.name} {self.rate:5.1f} Hz  dropped {self.dropped}{state}"

    def read(self) -> DepthFrame | ColourFrame | None:
        if self._lost_at is not None and not self._reopened and not self._reconnect():
            return self._hold()
        try:
            got = self.grab(self.STALL_S)
        except EndOfStream:
            return None
        if got is None:
            self._lose(self.stalled())
            return self._hold()
        now = time.monotonic()
        if self._lost_at is not None:
            print(f"issv: {self.name}: camera back after {now - self._lost_at:.1f} s", file=sys.stderr)
            self._lost_at, self._reopened = None, False
        self._arrivals.append(now)
        self.dropped += got.skipped
        self._first_time = got.device_time if self._first_time is None else self._first_time
        self._emit(got.image, self._base + got.device_time - self._first_time)
        self.handover_s = time.perf_counter() - got.received  # what this source adds to the latency
        return self._last

    def _emit(self, image: np.ndarray, timestamp: float) -> None:
        self._last, self._last_image = self.frame(image, self._count, timestamp), image
        self._count += 1

    def _lose(self, why: str) -> None:
        relapse = self._lost_at is not None  # reopened, but lost again before an image came
        if not relapse or why != self._why:
            print(f"issv: {self.name}: {why}; the show goes on with the last frame, reconnecting every "
                  f"{self.RETRY_S:g} s", file=sys.stderr)
        now = time.monotonic()
        self._why, self._reopened, self._retry_at = why, False, now + self.RETRY_S
        if not relapse:
            self._lost_at = now
        self._arrivals.clear()
        try:
            self.disconnect()
        except Exception:  # the device is gone: releasing it may fail too
            pass

    def _reconnect(self) -> bool:
        now = time.monotonic()
        if now < self._retry_at:
            return False
        self._retry_at = now + self.RETRY_S
        try:
            self.connect()
        except (UserError, RuntimeError, OSError):
            return False
        self._reopened = True  # back once an image comes (read says so)
        if self._last is not None:  # time goes on from the last frame held, whatever the device's clock says
            self._base, self._first_time = self._last.timestamp + 1.0 / self.fps, None
        return True

    def _hold(self) -> DepthFrame | ColourFrame:
        """The last frame again, one camera period later (a blank one if it never sent any)."""
        time.sleep(1.0 / self.fps)
        if self._last is None:
            self._emit(self.blank(), 0.0)
        else:
            self._emit(self._last_image, self._last.timestamp + 1.0 / self.fps)
        return self._last
