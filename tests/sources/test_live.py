"""What every camera source does when its camera misbehaves: drops, an unplug mid-show, a replug.

No USB camera can be plugged in or pulled out here, so the camera is a scripted stand-in: a
LiveCamera whose `grab()` delivers numbered frames until the test "unplugs" it. Everything else
(holding the last frame, saying so once, reconnecting, the rate and drops on the HUD, a show
that goes on) is the real code every camera source runs.
"""
from __future__ import annotations

import threading
import time

import numpy as np
from backends.engine.backend import OpenISSBackend
from host import Intrinsics
from host.errors import UserError
from host.loop import Limits, Show
from host.metrics import Metrics
from host.contracts import Stage
from host.render.hud import lines
from host.status import line
from sources.live import EndOfStream, Grabbed, LiveCamera


class ScriptedCamera(LiveCamera):
    """Stands in for a USB camera: frames until `plugged` is cleared, every 4th frame skips 2."""

    name = "scripted"
    fps = 100.0
    STALL_S, RETRY_S = 0.15, 0.05

    def __init__(self, options=None, frames: int | None = None) -> None:
        super().__init__(options)
        self.plugged = threading.Event()
        self.plugged.set()
        self.frames, self.number, self.connects, self.skipped = frames, 0, 0, 0

    def connect(self) -> None:
        if not self.plugged.is_set():
            raise UserError("source 'scripted': no camera")
        self.connects += 1
        self.width, self.height, self.intrinsics = 32, 24, Intrinsics(30, 30, 16, 12)

    def grab(self, timeout: float) -> Grabbed | None:
        if self.frames is not None and self.number >= self.frames:
            raise EndOfStream
        if not self.plugged.is_set():
            time.sleep(timeout)
            return None
        time.sleep(1 / self.fps)
        skipped = 2 if self.number % 4 == 3 else 0
        self.number += 1 + skipped
        self.skipped += skipped
        return Grabbed(np.full((24, 32), 1000 + self.number, np.uint16), self.number / self.fps, skipped)


def test_an_unplugged_camera_is_reported_once_held_and_reconnected(capfd):
    cam = ScriptedCamera()
    cam.open()
    before = [cam.read() for _ in range(8)]
    cam.plugged.clear()
    held = [cam.read() for _ in range(6)]
    assert "LOST" in cam.health() and cam.rate == 0
    cam.plugged.set()
    after = [cam.read()]
    while np.array_equal(after[-1].data, before[-1].data) and len(after) < 100:  # until the next retry
        after.append(cam.read())
    err = capfd.readouterr().err
    assert err.count("no depth frame for 0.15 s (unplugged?)") == 1 and err.count("camera back after") == 1
    assert all(np.array_equal(f.data, before[-1].data) for f in held)  # the show goes on with the last frame
    assert after[-1].data[0, 0] > before[-1].data[0, 0] and cam.connects == 2
    frames = before + held + after
    assert [f.frame_id for f in frames] == list(range(len(frames)))
    assert all(b.timestamp > a.timestamp for a, b in zip(frames, frames[1:]))
    assert "LOST" not in cam.health()


def test_frames_the_device_skipped_are_counted_and_its_rate_measured():
    cam = ScriptedCamera()
    cam.open()
    for _ in range(12):
        cam.read()
    assert cam.dropped == cam.skipped > 0 and f"dropped {cam.skipped}" in cam.health()
    assert 20 < cam.rate <= 110  # it sleeps 10 ms per frame: under 100 Hz, however loaded the machine


def test_a_camera_missing_at_the_start_still_gives_frames_of_its_size_until_it_comes():
    cam = ScriptedCamera()
    cam.open()
    cam.plugged.clear()
    cam._lose("test")
    frame = cam.read()
    assert frame.data.shape == (24, 32) and not frame.data.any()


def test_the_hud_and_status_line_show_the_cameras_own_rate_and_drops():
    cam = ScriptedCamera(frames=1000)
    show = Show(OpenISSBackend(cam), [], Stage((64, 48), 60.0, "openiss"), limits=Limits(frames=40))
    metrics = show.run()
    assert metrics.frames == 40
    source = lines(metrics)[-2]  # the source's own line, above the layers' GPU times
    assert source == cam.health() and cam.health() in line(metrics)
    assert source.startswith("scripted") and "dropped" in source


def test_file_sources_show_their_frame_rate_instead():
    assert lines(Metrics("truth", 25.0))[-2] == "source  25.0 Hz"
