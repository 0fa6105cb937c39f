"""`webcam` on a video file written here by OpenCV, and on a stand-in for a camera (no camera exists
on this machine)."""
import json
import threading
import time

import numpy as np
import pytest

import sources.webcam as webcam
from host import ColourFrame
from host.cli import main as issv
from host.errors import UserError
from sources.webcam import WebcamOptions, WebcamSource


def _video(path, frames=12, size=(320, 240), fps=24.0):
    import cv2
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), fps, size)
    for i in range(frames):
        bgr = np.zeros((size[1], size[0], 3), np.uint8)
        bgr[:, : size[0] // 2] = (255, 0, 0)  # blue on the left half: BGR
        bgr[10:20, 10 + i * 5: 20 + i * 5] = 255
        writer.write(bgr)
    writer.release()
    return path


def test_a_video_gives_rgb_colour_frames_at_the_asked_size_with_its_own_clock(tmp_path):
    source = WebcamSource(WebcamOptions(path=str(_video(tmp_path / "v.avi")), width=160, height=120, hfov_deg=60))
    source.open()
    frames = []
    while (frame := source.read()) is not None:
        frames.append(frame)
    source.close()
    assert len(frames) == 12 and source.fps == pytest.approx(24.0) and not source.live
    first = frames[0]
    assert first.rgb.shape == (120, 160, 3) and not first.rgb.flags.writeable and not first.mirrored
    assert first.rgb[60, 20, 2] > 200 and first.rgb[60, 20, 0] < 50  # blue, in RGB order
    assert [f.timestamp for f in frames] == pytest.approx([i / 24 for i in range(12)], abs=1e-3)
    assert first.intrinsics.fx == pytest.approx(80 / np.tan(np.radians(30)))


def test_mirror_flips_the_image_and_says_so(tmp_path):
    source = WebcamSource(WebcamOptions(path=str(_video(tmp_path / "v.avi")), width=320, height=240, mirror=True))
    source.open()
    frame = source.read()
    source.close()
    assert frame.mirrored and frame.rgb[120, 300, 2] > 200  # the blue half is now on the right


def test_device_or_path_and_one_clear_error_when_it_cannot_open(tmp_path, capfd):
    with pytest.raises(ValueError, match="either device"):
        WebcamOptions()
    source = WebcamSource(WebcamOptions(path=str(tmp_path / "missing.mp4")))
    with pytest.raises(UserError, match="source 'webcam': cannot open video .*missing.mp4 .does the file exist"):
        source.open()
    camera = WebcamSource(WebcamOptions(device=7))  # no camera on this machine
    with pytest.raises(UserError, match="source 'webcam': cannot open camera 7 .is it plugged in"):
        camera.open()
    assert capfd.readouterr().err == ""  # OpenCV's own lines, one per capture backend it tried, are kept out


def test_frames_read_ahead_come_in_order_and_closing_early_does_not_hang(tmp_path):
    """Decoded on a thread of its own: every frame of a file once, in order, then None for good;
    a source closed with frames still decoded ahead stops at once."""
    import time
    path = _video(tmp_path / "v.avi", frames=30)
    source = WebcamSource(WebcamOptions(path=str(path), width=320, height=240))
    source.open()
    time.sleep(0.2)  # the reader runs ahead and waits: a file's frames are never dropped
    ids = []
    while (frame := source.read()) is not None:
        ids.append(frame.frame_id)
    assert ids == list(range(30)) and source.read() is None and source.dropped == 0
    source.close()
    looped = WebcamSource(WebcamOptions(path=str(path), width=320, height=240, loop=True))
    looped.open()
    assert [looped.read().frame_id for _ in range(45)] == list(range(45))  # past the end, again
    start = time.monotonic()
    looped.close()
    assert time.monotonic() - start < 1.0


class StandInCamera:
    """Stands in for cv2.VideoCapture on a USB webcam (none can be plugged in or pulled out here):
    numbered images at 100 Hz while `plugged` is set; unplugged, it cannot be opened and every read
    fails, as OpenCV's V4L2 capture does. The source's own code does everything else."""

    plugged = threading.Event()
    opened = 0

    def __init__(self, device):
        self.open = isinstance(device, int) and self.plugged.is_set()
        type(self).opened += self.open
        self.number = 0

    def isOpened(self):
        return self.open

    def set(self, prop, value):
        return True

    def read(self):
        time.sleep(0.01)
        if not (self.open and self.plugged.is_set()):
            return False, None
        self.number += 1
        return True, np.full((24, 32, 3), self.number % 256, np.uint8)

    def release(self):
        self.open = False


def test_a_camera_unplugged_mid_show_is_said_once_held_and_reopened_so_the_show_goes_on(monkeypatch, capfd):
    import cv2
    monkeypatch.setattr(cv2, "VideoCapture", StandInCamera)
    monkeypatch.setattr(WebcamSource, "STALL_S", 0.15)
    monkeypatch.setattr(WebcamSource, "RETRY_S", 0.05)
    StandInCamera.plugged.set()
    source = WebcamSource(WebcamOptions(device=0, width=32, height=24, fps=100))
    source.open()
    before = [source.read() for _ in range(5)]
    StandInCamera.plugged.clear()
    during = [source.read()]  # the images decoded before the unplug, then the first held frame
    while "LOST" not in source.health():
        during.append(source.read())
    held = [source.read() for _ in range(5)]
    StandInCamera.plugged.set()
    after = [source.read()]
    while np.array_equal(after[-1].rgb, held[-1].rgb) and len(after) < 200:  # until the next retry
        after.append(source.read())
    source.close()
    err = capfd.readouterr().err
    assert err.count("webcam: no colour frame for 0.15 s (unplugged?)") == 1 and err.count("camera back after") == 1
    last_seen = (before + during)[-2].rgb  # the show goes on with the last image the camera sent
    assert all(isinstance(f, ColourFrame) and np.array_equal(f.rgb, last_seen) for f in [during[-1]] + held)
    assert not np.array_equal(after[-1].rgb, last_seen) and StandInCamera.opened == 2
    frames = before + during + held + after
    assert all(b.frame_id > a.frame_id and b.timestamp > a.timestamp for a, b in zip(frames, frames[1:]))
    assert "LOST" not in source.health()


def test_issv_list_names_each_camera_by_the_index_a_profile_gives_and_what_keeps_one_closed(
        tmp_path, monkeypatch, capsys):
    """Linux's sysfs, as V4L2 lays it out for a USB camera with two video nodes (capture and metadata)
    and a second camera whose node this user may not open (its /dev entry is left out here)."""
    usb_camera = tmp_path / "usb" / "1-2"
    interface = usb_camera / "1-2:1.0"
    interface.mkdir(parents=True)
    (usb_camera / "serial").write_text("SN0001\n")
    (usb_camera / "bcdDevice").write_text("0019\n")
    for number, index in ((0, 0), (1, 1), (10, 0)):
        node = tmp_path / "video4linux" / f"video{number}"
        node.mkdir(parents=True)
        (node / "name").write_text(f"Camera {number}\n")
        (node / "index").write_text(f"{index}\n")
        (node / "device").symlink_to(interface)
    (tmp_path / "dev").mkdir()
    (tmp_path / "dev" / "video0").write_bytes(b"")
    monkeypatch.setattr(webcam, "V4L2_SYSFS", tmp_path / "video4linux")
    monkeypatch.setattr(webcam, "DEVFS", tmp_path / "dev")
    assert issv(["list", "--json"]) == 0
    found = {s["name"]: s for s in json.loads(capsys.readouterr().out)["sources"]}["webcam"]["devices"]
    assert [(d["model"], d["serial"], d["firmware"]) for d in found] == [
        ("Camera 0 (device = 0)", "SN0001", "0019"), ("Camera 10 (device = 10)", "SN0001", "0019")]
    assert found[0]["problem"] is None and "sudo usermod -aG video" in found[1]["problem"]


def test_a_video_whose_frame_cannot_be_decoded_ends_with_one_line_naming_it(tmp_path, monkeypatch):
    """Whatever decoding raises on, the reader thread says so and the show hears it, instead of waiting
    for a frame that never comes."""
    decode = WebcamSource._decode

    def third_fails(self):
        self.decoded = getattr(self, "decoded", 0) + 1
        if self.decoded == 3:
            raise ValueError("a broken packet")
        return decode(self)

    monkeypatch.setattr(WebcamSource, "_decode", third_fails)
    path = _video(tmp_path / "v.avi")
    source = WebcamSource(WebcamOptions(path=str(path)))
    source.open()
    assert [source.read().frame_id for _ in range(2)] == [0, 1]
    with pytest.raises(UserError, match=f"source 'webcam': video {path}: cannot decode a frame: a broken packet"):
        source.read()
    source.close()


def test_a_camera_frame_that_cannot_be_decoded_is_said_with_its_error_and_the_camera_reopened(monkeypatch, capfd):
    """Live, the show goes on with the last frame (a camera is reopened as after an unplug), and the line
    says what went wrong at once, instead of waiting the stall time and guessing at an unplug."""
    import cv2
    decode = WebcamSource._decode
    calls = []

    def third_fails(self):
        calls.append(1)
        if len(calls) == 3:
            raise ValueError("a broken packet")
        return decode(self)

    monkeypatch.setattr(cv2, "VideoCapture", StandInCamera)
    monkeypatch.setattr(WebcamSource, "_decode", third_fails)
    monkeypatch.setattr(WebcamSource, "RETRY_S", 0.05)
    StandInCamera.plugged.set()
    source = WebcamSource(WebcamOptions(device=0, width=32, height=24, fps=100))
    source.open()
    frames = [source.read() for _ in range(3)]
    start = time.monotonic()
    while "LOST" not in source.health():
        frames.append(source.read())
    lost_after = time.monotonic() - start
    while "LOST" in source.health():
        frames.append(source.read())
    source.close()
    err = capfd.readouterr().err
    assert err.count("webcam: camera 0: cannot decode a frame: a broken packet; the show goes on") == 1
    assert "unplugged" not in err and err.count("camera back after") == 1
    assert lost_after < WebcamSource.STALL_S / 2
    assert all(b.frame_id > a.frame_id for a, b in zip(frames, frames[1:]))


def test_a_camera_whose_every_frame_cannot_be_decoded_is_said_once_and_stays_lost(monkeypatch, capfd):
    """Reopened every retry, it fails again before any image: the line is not repeated each time, and
    the camera is not said to be back (the HUD keeps saying LOST) until an image comes."""
    import cv2

    def always_fails(self):
        raise ValueError("a broken packet")

    monkeypatch.setattr(cv2, "VideoCapture", StandInCamera)
    monkeypatch.setattr(WebcamSource, "_decode", always_fails)
    monkeypatch.setattr(WebcamSource, "RETRY_S", 0.05)
    StandInCamera.plugged.set()
    opened = StandInCamera.opened
    source = WebcamSource(WebcamOptions(device=0, width=32, height=24, fps=100))
    source.open()
    frames = [source.read() for _ in range(60)]
    healthy = source.health()
    source.close()
    err = capfd.readouterr().err
    assert StandInCamera.opened - opened >= 4  # it was reopened, and failed again, several times
    assert err.count("cannot decode a frame: a broken packet") == 1 and "camera back" not in err
    assert "LOST" in healthy
    assert all(b.frame_id > a.frame_id for a, b in zip(frames, frames[1:]))  # the show went on
