"""`webcam`: colour frames from an RGB camera (OpenCV capture) or a video file.

A camera (`device`, an index) is live: `read()` waits for the device, and a camera that stalls, is
unplugged or sends a frame it cannot decode is handled as every camera source handles it
(sources/live.py). A file (`path`) is paced by the host from its frames' timestamps (the video's
own clock). `width`, `height` and `fps` ask the camera for a mode (it may pick the nearest it has;
the frames say what came) and, for a file, resize its frames and leave its rate alone. The camera's
horizontal field of view (`hfov_deg`, most webcams 60-70 degrees) gives the intrinsics that place
what a backend finds in millimetres.
Frames are decoded and converted to RGB a frame or two ahead on a thread of their own, so the
second core does it while the backend works on the frame before.
"""
from __future__ import annotations

import contextlib
import dataclasses
import os
import queue
import sys
import threading
import time
from pathlib import Path
from typing import ClassVar, Iterator

import numpy as np

from pydantic import BaseModel, ConfigDict, Field, model_validator

from host import ColourFrame, DeviceInfo, Intrinsics
from host.errors import UserError
from host.options import ProfilePath
from sources import usb
from sources.live import EndOfStream, Grabbed, LiveCamera

AHEAD = 2  # frames decoded ahead of the backend
V4L2_SYSFS = Path("/sys/class/video4linux")
DEVFS = Path("/dev")


class WebcamOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    device: int | None = Field(None, ge=0, description="camera index (0: the first camera); or give path")
    path: ProfilePath | None = Field(None, description="a video file to play instead of a camera")
    width: int = Field(640, gt=0, description="frame width in pixels")
    height: int = Field(480, gt=0, description="frame height in pixels")
    fps: float = Field(30.0, gt=0, description="frames per second asked of the camera")
    hfov_deg: float = Field(62.0, gt=10, lt=170, description="the camera's horizontal field of view, degrees")
    mirror: bool = Field(False, description="flip the image as a mirror (a selfie view)")
    loop: bool = Field(False, description="a file starts again at its end")

    @model_validator(mode="after")
    def _one(self):
        if (self.device is None) == (self.path is None):
            raise ValueError("give either device (a camera index, e.g. 0) or path (a video file)")
        return self


def v4l2_cameras() -> list[DeviceInfo]:
    """The cameras Linux's V4L2 sees, by the index `device` takes (a camera's capture node: the first
    of its video nodes; the others carry metadata), with the group this user lacks to open one."""
    found = []
    for folder in sorted(V4L2_SYSFS.glob("video*"), key=lambda f: int(f.name[5:] or 0)):
        if usb.attribute(folder, "index") not in ("", "0"):
            continue
        node, on_usb = DEVFS / folder.name, folder / "device" / ".."  # the USB device, above its interface
        problem = None if os.access(node, os.R_OK | os.W_OK) else (
            f"no permission on {node}: add yourself to its group (sudo usermod -aG video $USER) and log in again")
        found.append(DeviceInfo(f"{usb.attribute(folder, 'name') or folder.name} (device = {folder.name[5:]})",
                                usb.attribute(on_usb, "serial"), usb.attribute(on_usb, "bcdDevice"), (), problem))
    return found


@contextlib.contextmanager
def _opencv_silent(cv2) -> Iterator[None]:
    """OpenCV's own log lines (several per failed open, from every capture backend it tries) off."""
    level = cv2.utils.logging.getLogLevel()
    cv2.utils.logging.setLogLevel(cv2.utils.logging.LOG_LEVEL_SILENT)
    try:
        yield
    finally:
        cv2.utils.logging.setLogLevel(level)


class WebcamSource(LiveCamera):
    """OpenCV capture: frames as RGB ColourFrames. A camera that stalls or is unplugged is said once,
    the show goes on with its last frame and the camera is reopened until it answers, as the depth
    cameras are (sources/live.py); a file plays to its end."""

    name = "webcam"
    Options = WebcamOptions
    frames: ClassVar[str] = "colour"

    @classmethod
    def devices(cls) -> list[DeviceInfo] | None:
        """Cameras connected now (V4L2, so Linux only; None elsewhere: not known)."""
        return v4l2_cameras() if sys.platform.startswith("linux") else None

    def __init__(self, options: WebcamOptions | None = None) -> None:
        super().__init__(options)
        o = self.options
        self.live = o.device is not None  # an instance attribute: a camera is live, a file is paced
        self.fps = o.fps
        self.width, self.height = o.width, o.height
        self.intrinsics = self._intrinsics(o.width, o.height)
        self._capture = None

    def _intrinsics(self, width: int, height: int) -> Intrinsics:
        import math
        vfov = math.degrees(2 * math.atan(math.tan(math.radians(self.options.hfov_deg) / 2) * height / width))
        return Intrinsics.from_fov(width, height, self.options.hfov_deg, vfov)

    def connect(self) -> None:
        import cv2
        o = self.options
        with _opencv_silent(cv2):  # our one line says it; a reconnect tried every second stays quiet
            capture = cv2.VideoCapture(o.device if self.live else str(o.path))
        if not capture.isOpened():
            capture.release()
            raise UserError(f"source 'webcam': cannot open {self._what()} " + (
                "(is it plugged in, and not in use by another program?)" if self.live else
                "(does the file exist, in a format OpenCV reads?)"))
        if self.live:
            capture.set(cv2.CAP_PROP_FRAME_WIDTH, o.width)
            capture.set(cv2.CAP_PROP_FRAME_HEIGHT, o.height)
            capture.set(cv2.CAP_PROP_FPS, o.fps)
        else:
            rate = capture.get(cv2.CAP_PROP_FPS)
            self.fps = rate if rate and rate > 0 else o.fps
        self._capture, self._start = capture, time.monotonic()
        self._ended, self._failure = False, ""
        self._made_way = self._reported = 0  # frames that made way for newer ones, and those reported
        self._ahead: queue.Queue[Grabbed | None] = queue.Queue(maxsize=AHEAD)
        self._stop = threading.Event()
        self._reader = threading.Thread(target=self._read_ahead, name="issv-webcam", daemon=True)
        self._reader.start()

    def _what(self) -> str:
        return f"camera {self.options.device}" if self.live else f"video {self.options.path}"

    def grab(self, timeout: float) -> Grabbed | None:
        """The next image decoded: a file's every one in order, waiting as long as it takes; a
        camera's newest, None after `timeout` without one."""
        if self._ended:
            raise EndOfStream
        try:
            got = self._ahead.get(timeout=timeout if self.live else None)
        except queue.Empty:
            return None
        if got is None:
            if self.live:  # a frame it could not decode stopped the reader: the camera is lost now
                return None
            self._ended = True
            if self._failure:
                raise UserError(f"source 'webcam': {self._failure}")
            raise EndOfStream
        skipped, self._reported = self._made_way - self._reported, self._made_way
        return dataclasses.replace(got, skipped=skipped)

    def stalled(self) -> str:
        return self._failure or super().stalled()

    def frame(self, image: np.ndarray, frame_id: int, timestamp: float) -> ColourFrame:
        return ColourFrame(image, self.intrinsics, frame_id, timestamp, time.time(), self.options.mirror)

    def blank(self) -> np.ndarray:
        return np.zeros((self.height, self.width, 3), np.uint8)

    def _read_ahead(self) -> None:
        """Decoding and colour conversion on a thread of their own, beside the backend's work on the
        frame before. A file's frames all wait their turn; a camera's stale ones make way (dropped)."""
        while not self._stop.is_set():
            try:
                got = self._decode()
            except Exception as error:  # OpenCV's own errors, or an image it cannot convert: said by read()
                self._failure = f"{self._what()}: cannot decode a frame: {error}"
                got = None
            if got is None and self.live and not self._failure:
                return  # the camera stopped answering: grab() times out, and the camera is reopened
            while True:
                try:
                    self._ahead.put(got, timeout=0.1)
                    break
                except queue.Full:
                    if self._stop.is_set():
                        return
                    if self.live:  # the backend is behind: the oldest frame goes, the newest waits
                        try:
                            self._ahead.get_nowait()
                            self._made_way += 1
                        except queue.Empty:
                            pass
            if got is None:  # a file's end
                return

    def _decode(self) -> Grabbed | None:
        import cv2
        o = self.options
        ok, bgr = self._capture.read()
        if not ok and not self.live and o.loop:
            self._capture.set(cv2.CAP_PROP_POS_FRAMES, 0)
            ok, bgr = self._capture.read()
        if not ok:
            return None
        if bgr.shape[1] != o.width or bgr.shape[0] != o.height:
            bgr = cv2.resize(bgr, (o.width, o.height), interpolation=cv2.INTER_AREA)
        rgb = cv2.cvtColor(cv2.flip(bgr, 1) if o.mirror else bgr, cv2.COLOR_BGR2RGB)
        rgb.flags.writeable = False
        t = time.monotonic() - self._start if self.live else self._capture.get(cv2.CAP_PROP_POS_MSEC) / 1000.0
        return Grabbed(rgb, t)

    def health(self) -> str | None:
        """A camera's rate, frames dropped because the backend was behind, and whether it is there."""
        return super().health() if self.live else None

    def disconnect(self) -> None:
        if self._capture is None:
            return
        self._stop.set()
        self._reader.join(timeout=2.0)
        if not self._reader.is_alive():  # a read stuck on a vanished camera keeps its capture
            self._capture.release()
        self._capture = None
