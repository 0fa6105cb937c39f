"""Files a show writes: an mp4 video (OpenCV's 'mp4v') and a PNG snapshot of the last frame."""
from __future__ import annotations

import time
from pathlib import Path

import cv2
import moderngl
import numpy as np

from host.errors import UserError

VIDEO_FPS_MAX = 30.0  # the sensor's rate: more frames would repeat the same tracking data


def read_bgr(fbo: moderngl.Framebuffer) -> np.ndarray:
    """The framebuffer as an OpenCV image: (H, W, 3) uint8 BGR, row 0 at the top."""
    w, h = fbo.size
    rgb = np.frombuffer(fbo.read(components=3, alignment=1), np.uint8).reshape(h, w, 3)
    return cv2.cvtColor(rgb[::-1], cv2.COLOR_RGB2BGR)


def check_folder(path: Path, what: str) -> None:
    if not path.parent.is_dir():
        raise UserError(f"{path}: cannot write the {what}: folder {path.parent} does not exist")


class VideoOutput:
    """Writes frames at a fixed rate in wall-clock time, so the video plays at the show's speed
    whether the renderer runs faster (frames are skipped) or slower (frames are repeated)."""

    def __init__(self, path: str | Path, size: tuple[int, int], fps: float) -> None:
        self.path = Path(path)
        check_folder(self.path, "video")
        self.fps = min(fps, VIDEO_FPS_MAX)
        self.writer = cv2.VideoWriter(str(self.path), cv2.VideoWriter_fourcc(*"mp4v"), self.fps, size)
        if not self.writer.isOpened():
            raise UserError(f"{self.path}: OpenCV cannot open an mp4 ('mp4v') video for writing here")
        self.written = 0
        self._start: float | None = None

    def write(self, fbo: moderngl.Framebuffer) -> None:
        now = time.perf_counter()
        self._start = now if self._start is None else self._start
        due = int((now - self._start) * self.fps) + 1
        if due <= self.written:
            return
        image = read_bgr(fbo)
        for _ in range(min(due - self.written, int(self.fps))):  # a long stall repeats at most 1 s
            self.writer.write(image)
        self.written = due

    def close(self) -> None:
        self.writer.release()


def save_snapshot(path: str | Path, fbo: moderngl.Framebuffer) -> None:
    path = Path(path)
    check_folder(path, "snapshot")
    if not cv2.imwrite(str(path), read_bgr(fbo)):
        raise UserError(f"{path}: OpenCV could not write the PNG snapshot (is the name a .png?)")
