"""`kinect`: a Kinect v1 (Xbox 360 or Kinect for Windows) through libfreenect.

Uses Debian's `libfreenect0.5` through the PyPI `freenect` bindings (`pip install 'issv[kinect]'`,
built against `libfreenect-dev`). libfreenect's event loop runs on a thread of its own
(`freenect.runloop`, which releases the GIL while it waits for USB); its depth callback only
replaces the newest image, so `read()` always gets the latest and counts the ones it never saw.

Depth is requested as the sensor's 11-bit disparities and converted to millimetres with the same
Kinect v1 fit as the `fakenect` source (sources/fakenect.py). `registered = true` asks libfreenect
for FREENECT_DEPTH_REGISTERED instead: millimetres from the device's own factory calibration,
aligned to the colour camera. Tilt and LED are left alone unless the profile sets them.

Replays: libfreenect's `fakenect` library stands in for libfreenect itself (`fakenect DUMP issv run
...` puts it first on LD_LIBRARY_PATH and sets FAKENECT_PATH), so a dump plays through exactly the
code that reads a live Kinect. Debian's fakenect plays 11-bit depth only, has no registration and
ends with the dump: with FAKENECT_PATH set the source ends too, instead of reconnecting.

Needs a Kinect plugged in (untested here): `registered`, `tilt_degrees`, `led`, more than one
device (`index` > 0), and the unplug/reconnect path on real USB.
"""
from __future__ import annotations

import os
import sys
import threading
import time
from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from host import DeviceInfo, Intrinsics
from host.errors import UserError
from sources import usb
from sources.fakenect import KINECT_V1_FOV_DEG, disparity_to_mm
from sources.live import EndOfStream, Grabbed, LiveCamera

KINECT_IDS = {("045e", "02ae"): "Kinect v1 (Xbox 360) camera", ("045e", "02bf"): "Kinect for Windows camera"}
CLOCK_HZ = 60e6  # the Kinect's frame timestamps count a 60 MHz clock
REGISTERED_INTRINSICS = Intrinsics(525.0, 525.0, 319.5, 239.5)  # the colour camera registered depth is aligned to
MODES = ("640x480 @ 30 fps, 11-bit disparity -> mm", "640x480 @ 30 fps, registered mm (live device only)")
INSTALL = "pip install 'issv[kinect]' (builds against Debian's libfreenect-dev: apt-get install libfreenect-dev)"
LEDS = {"off": "LED_OFF", "green": "LED_GREEN", "red": "LED_RED", "yellow": "LED_YELLOW",
        "blink_green": "LED_BLINK_GREEN", "blink_red_yellow": "LED_BLINK_RED_YELLOW"}


def load_freenect():
    """`import freenect` with lazy symbol binding. The module links libfreenect_sync, which refers
    to registration functions Debian's fakenect library does not have; bound eagerly (Python's
    default) the import fails under fakenect, bound lazily those functions are simply never called."""
    flags = sys.getdlopenflags()
    sys.setdlopenflags(os.RTLD_LAZY)
    try:
        import freenect
    finally:
        sys.setdlopenflags(flags)
    return freenect


def replaying() -> str | None:
    """The fakenect dump being replayed in place of a Kinect, if any."""
    return os.environ.get("FAKENECT_PATH") or None


class KinectOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    index: int = Field(0, ge=0, description="which Kinect, when several are plugged in (0: the first)")
    registered: bool = Field(False, description="libfreenect's registered depth (mm aligned to colour)")
    tilt_degrees: float | None = Field(None, ge=-30, le=30, description="tilt the motor at start (unset: leave it)")
    led: Literal["off", "green", "red", "yellow", "blink_green", "blink_red_yellow"] | None = Field(
        None, description="set the LED at start (unset: leave it)")


class KinectSource(LiveCamera):
    name = "kinect"
    Options = KinectOptions
    fps = 30.0
    width, height = 640, 480

    @classmethod
    def availability(cls) -> str | None:
        try:
            load_freenect()
        except ImportError as error:
            if "libfreenect" in str(error):
                return f"libfreenect is missing ({error}): apt-get install libfreenect0.5"
            return f"the PyPI package `freenect` (libfreenect bindings) is missing: {INSTALL}"
        return None

    @classmethod
    def devices(cls) -> list[DeviceInfo]:
        if replaying():
            return [DeviceInfo("fakenect replay", replaying(), "", MODES[:1])]
        found = usb.find(KINECT_IDS)
        return [DeviceInfo(d.model, d.serial, d.firmware, MODES, usb.permission_problem([d])) for d in found]

    def connect(self) -> None:
        fn = self._fn = load_freenect()
        if self.options.registered and replaying():
            raise UserError("source 'kinect': registered = true needs a live Kinect; libfreenect's fakenect "
                            "replays 11-bit depth only (set registered = false)")
        ctx = fn.init()
        if ctx is None:
            raise UserError("source 'kinect': libfreenect could not start (libusb failed to initialise)")
        count = fn.num_devices(ctx)
        dev = fn.open_device(ctx, self.options.index) if count > self.options.index else None
        if dev is None:
            fn.shutdown(ctx)
            raise UserError(f"source 'kinect': {self._why_not(count)}")
        fmt = fn.DEPTH_REGISTERED if self.options.registered else fn.DEPTH_11BIT
        fn.set_depth_mode(dev, fn.RESOLUTION_MEDIUM, fmt)
        if self.options.tilt_degrees is not None:
            fn.set_tilt_degs(dev, self.options.tilt_degrees)
        if self.options.led is not None:
            fn.set_led(dev, getattr(fn, LEDS[self.options.led]))
        self.intrinsics = (REGISTERED_INTRINSICS if self.options.registered
                           else Intrinsics.from_fov(self.width, self.height, *KINECT_V1_FOV_DEG))
        self._ctx, self._dev = ctx, dev
        self._cond = threading.Condition()
        self._raw: np.ndarray | None = None
        self._stamp, self._wraps, self._seq, self._taken = 0, 0, 0, 0
        self._stop = self._ended = False
        self._thread = threading.Thread(target=self._loop, name="issv-kinect", daemon=True)
        self._thread.start()

    def _why_not(self, count: int) -> str:
        if count > self.options.index:
            problem = usb.permission_problem(usb.find(KINECT_IDS))
            return problem or f"libfreenect found {count} Kinect(s) but could not open index {self.options.index}"
        found = usb.find(KINECT_IDS)
        if len(found) > self.options.index:
            return usb.permission_problem(found) or "the Kinect is on USB but libfreenect cannot open it"
        return (f"no Kinect v1 at index {self.options.index} ({count} found): plug one in (USB 045e:02ae or "
                f"045e:02bf) with its power supply")

    def _loop(self) -> None:
        fn = self._fn

        def body(*_):
            if self._stop:
                raise fn.Kill

        fn.runloop(depth=self._on_depth, body=body, dev=self._dev)
        with self._cond:  # libfreenect's loop ended: the device failed, or the fakenect dump ended
            self._ended = True
            self._cond.notify_all()

    def _on_depth(self, _dev, data: np.ndarray, timestamp: int) -> None:
        """libfreenect's callback: copy the image out of its buffer, replace the newest."""
        received = time.perf_counter()
        raw = np.array(data, copy=True)
        with self._cond:
            self._wraps += timestamp < self._stamp  # the 32-bit clock wraps every 71 s
            self._stamp = timestamp
            self._raw, self._time = raw, (self._wraps * 2**32 + timestamp) / CLOCK_HZ
            self._received = received
            self._seq += 1
            self._cond.notify_all()

    def grab(self, timeout: float) -> Grabbed | None:
        with self._cond:
            self._cond.wait_for(lambda: self._seq > self._taken or self._ended, timeout)
            if self._seq == self._taken:
                if self._ended and replaying():
                    raise EndOfStream
                return None
            skipped, self._taken = self._seq - self._taken - 1, self._seq
            raw, device_time, received = self._raw, self._time, self._received
        depth = raw if self.options.registered else disparity_to_mm(raw)
        return Grabbed(depth, device_time, skipped, received)

    def disconnect(self) -> None:
        dev = getattr(self, "_dev", None)
        if dev is None:
            return
        self._stop = True
        self._thread.join(timeout=2.0)
        if not self._thread.is_alive():  # a loop stuck on a vanished device keeps its handles
            self._fn.close_device(dev)
            self._fn.shutdown(self._ctx)
        self._dev = None
