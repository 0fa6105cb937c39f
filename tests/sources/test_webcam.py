"""`webcam` on a video file written here by OpenCV (no camera exists on this machine)."""
import numpy as np
import pytest

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


def test_device_or_path_and_a_clear_error_when_it_cannot_open(tmp_path):
    with pytest.raises(ValueError, match="either device"):
        WebcamOptions()
    source = WebcamSource(WebcamOptions(path=str(tmp_path / "missing.mp4")))
    with pytest.raises(UserError, match="source 'webcam': cannot open video"):
        source.open()


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
    assert ids == list(range(1, 31)) and source.read() is None and source.dropped == 0
    source.close()
    looped = WebcamSource(WebcamOptions(path=str(path), width=320, height=240, loop=True))
    looped.open()
    assert [looped.read().frame_id for _ in range(45)] == list(range(1, 46))  # past the end, again
    start = time.monotonic()
    looped.close()
    assert time.monotonic() - start < 1.0
