""".bag recordings written by librealsense itself, played back through the `realsense` source.

No RealSense camera is plugged in here, so the camera is librealsense's own `software_device`
(a device whose frames the test supplies) recorded by librealsense's own `recorder`: the file is
the library's real format, with the device's depth scale and intrinsics in it, read back by the
same pipeline code that opens a live camera. What needs a camera is listed in sources/realsense.py.
"""
from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
import pytest

from host import Intrinsics
from host.cli import main as issv
from host.errors import UserError
from sources.realsense import RealSenseOptions, RealSenseSource, write_bag
from tests.recordings import write_profile

rs = pytest.importorskip("pyrealsense2", reason="the realsense extra is not installed: pip install 'issv[realsense]'")

W, H, FPS = 640, 480, 30
FX, FY, PPX, PPY = 615.25, 614.75, 318.5, 243.25


def frame_pixels(i: int) -> np.ndarray:
    """A frame that says which frame it is, with a hole (0 = no reading) in the middle."""
    px = ((np.arange(W * H, dtype=np.uint32).reshape(H, W) * (i + 1) + 500 * i) % 60000 + 300).astype(np.uint16)
    px[200:240, 300:340] = 0
    return px


@pytest.fixture(scope="module")
def bag(tmp_path_factory) -> tuple[Path, list[np.ndarray]]:
    path = tmp_path_factory.mktemp("rs") / "take.bag"
    written = [frame_pixels(i) for i in range(12)]
    write_bag(path, written, Intrinsics(FX, FY, PPX, PPY), FPS, pace=True)
    return path, written


def play(**options) -> tuple[RealSenseSource, list]:
    source = RealSenseSource(RealSenseOptions(**options))
    source.open()
    try:
        return source, list(iter(source.read, None))
    finally:
        source.close()


def delivered(frames: list, written: list[np.ndarray]) -> list[int]:
    """Which written frame each played frame is, bit for bit (fails on any other content)."""
    ids = [next((i for i, w in enumerate(written) if np.array_equal(f.data, w)), None) for f in frames]
    assert None not in ids, "a played frame matches no written frame"
    return ids


def test_a_bag_plays_back_bit_exact_with_the_devices_intrinsics(bag):
    path, written = bag
    assert path.read_bytes()[:13] == b"#ROSBAG V2.0\n"  # a ROS 1 bag, as the RealSense Viewer writes
    source, frames = play(path=str(path), realtime=False)
    ids = delivered(frames, written)  # each frame bit for bit one of those written, in order
    assert ids == sorted(set(ids)) and ids[0] <= 1 and ids[-1] == 11
    # a starved machine may drop: counted, from the first frame delivered on (playback may start at
    # the second, as allowed above: nothing before it tells the source a frame was missed)
    assert len(ids) + source.dropped == 12 - ids[0] and len(ids) >= 10
    assert source.intrinsics.as_list() == pytest.approx([FX, FY, PPX, PPY])
    assert source.fps == FPS and source.depth_unit_mm == 1.0
    assert [f.timestamp for f in frames] == pytest.approx([(i - ids[0]) / FPS for i in ids], abs=1e-6)
    assert f"dropped {source.dropped}" in source.health() and not frames[0].mirrored


def test_a_scale_other_than_a_millimetre_is_converted(tmp_path):
    written = [frame_pixels(i) for i in range(3)]
    write_bag(tmp_path / "sr305.bag", written, Intrinsics(FX, FY, PPX, PPY), FPS, depth_units_m=0.000125)  # SR305
    source, frames = play(path=str(tmp_path / "sr305.bag"), realtime=False)
    assert source.depth_unit_mm == 0.125
    expected = [np.round(w * 0.125).astype(np.uint16) for w in written]
    ids = [next((i for i, e in enumerate(expected) if np.array_equal(f.data, e)), None) for f in frames]
    # every frame converted exactly, in order (librealsense's playback dropped one once on a busy machine)
    assert ids and None not in ids and ids == sorted(set(ids))


def test_realtime_playback_keeps_the_recorded_pace(bag):
    path, _ = bag
    start = time.monotonic()
    play(path=str(path))
    realtime = time.monotonic() - start
    assert realtime >= 11 / FPS * 0.8  # 12 frames recorded 1/30 s apart


def test_seek_starts_later_and_loop_runs_on_forward_in_time(bag):
    path, written = bag
    seeking, frames = play(path=str(path), realtime=False, seek=0.2)
    ids = delivered(frames, written)
    assert 1 < ids[0] < 11 and ids[-1] == 11  # ~6: the recorder stamped frames as paced
    assert all(b > a for a, b in zip(ids, ids[1:])) and seeking.dropped == 12 - ids[0] - len(ids)  # drops counted
    source = RealSenseSource(RealSenseOptions(path=str(path), realtime=False, loop=True))
    source.open()
    try:
        looped = [source.read() for _ in range(30)]
    finally:
        source.close()
    times = [f.timestamp for f in looped]
    assert all(b > a for a, b in zip(times, times[1:])) and times[-1] > 11 / FPS
    assert any(np.array_equal(f.data, written[0]) for f in looped[12:])  # the second pass


def test_filters_run_on_the_frames_and_decimation_scales_the_intrinsics(bag):
    path, written = bag
    source, frames = play(path=str(path), realtime=False, decimation=2, hole_filling=True, spatial=True,
                          temporal=True)
    assert frames[0].data.shape == (H // 2, W // 2) and (source.width, source.height) == (W // 2, H // 2)
    assert source.intrinsics.fx == pytest.approx(FX / 2, rel=0.01) and source.intrinsics.cx == pytest.approx(PPX / 2, abs=1)
    assert (written[0][200:240, 300:340] == 0).all() and (frames[0].data[100:120, 150:170] > 0).all()  # filled


def test_issv_run_plays_a_bag(bag, tmp_path):
    path, _ = bag
    prof = write_profile(tmp_path / "p.toml", {"name": "realsense", "path": str(path), "realtime": False,
                                               "loop": True})
    metrics = tmp_path / "m.json"
    assert issv(["run", str(prof), "--headless", "--no-reload", "--frames", "30", "--metrics-json", str(metrics)]) == 0
    assert json.loads(metrics.read_text())["frames"] == 30


def test_a_seek_past_the_end_or_a_mode_the_file_lacks_is_refused(bag):
    path, _ = bag
    with pytest.raises(UserError, match=r"seek = 100 s is past the recording's end"):
        play(path=str(path), seek=100)
    with pytest.raises(UserError, match=r"no depth stream at 1280x720 @ 30 fps in it"):
        play(path=str(path), width=1280, height=720)


def test_a_missing_or_foreign_file_says_so(tmp_path):
    with pytest.raises(UserError, match="no such RealSense recording"):
        play(path=str(tmp_path / "missing.bag"))
    (tmp_path / "bad.bag").write_bytes(b"not a bag")
    with pytest.raises(UserError, match="librealsense cannot play it"):
        play(path=str(tmp_path / "bad.bag"))


def test_without_a_camera_the_source_says_what_to_check():
    """No RealSense is plugged in here: starting the live camera must fail with a reason, not hang."""
    if rs.context().query_devices().size():
        pytest.skip("a RealSense camera is plugged in")
    with pytest.raises(UserError, match="cannot start any RealSense|no permission"):
        play()
    assert RealSenseSource.devices() == []


def test_issv_record_keeps_a_realsense_take_like_any_source(bag, tmp_path):
    from host.recording import Recording
    from tests.recordings import record_profile

    path, written = bag
    prof = write_profile(tmp_path / "p.toml", {"name": "realsense", "path": str(path), "realtime": False},
                         {"name": "openiss"})
    out = record_profile(prof, tmp_path / "take.mcap", "--frames", "10")
    with Recording(out) as rec:
        frames = list(rec.frames())
    # each recorded frame is one of the take's, bit for bit, in the take's order (a busy machine may
    # drop one between the source's thread and the show: newest wins, as with a camera)
    ids = delivered([f.depth for f in frames], written)
    assert len(frames) == 10 and ids == sorted(set(ids))
