"""`.oni` files through the real OpenNI2 runtime (Debian's libopenni2-0 + the `openni` bindings).

A real camera take (tests/data/openni-user, MIT-style, see its ATTRIBUTION.md) is checked against
a second reader written for the tests (tests/sources/onifile.py: the container and the 16zT codec
decoded in Python, nothing shared with OpenNI2's C++ player). A file made by OpenNI2's own Recorder
from its bundled `Dummy` device opens (streams, frame count, video mode) but delivers none of its
frames on this machine, so that test checks the source reports it clearly instead of hanging.
"""
from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from backends.engine.segmentation import SegmentationOptions, Segmenter
from host import Intrinsics, devices
from host.cli import main as issv
from host.errors import UserError
from sources.oni import OniOptions, OniSource
from tests.recordings import write_profile
from tests.sources.onifile import read_oni
from tests.sources.test_depth_images import hands_in

TAKE = Path(__file__).resolve().parents[1] / "data" / "openni-user" / "user_new.oni"

RECORD_DUMMY = """
import sys
from openni import openni2
from host.devices import bindings_dir, find_runtime
openni2.initialize(str(bindings_dir(find_runtime())))
device = openni2.Device(b"Dummy")
stream = device.create_depth_stream()
stream.start()
recorder = openni2.Recorder(sys.argv[1].encode())
recorder.attach(stream)
recorder.start()
for _ in range(10):
    stream.read_frame()
recorder.stop(); recorder.close(); stream.stop(); stream.close(); device.close()
"""

needs_runtime = pytest.mark.skipif(OniSource.availability() is not None, reason=str(OniSource.availability()))


def test_availability_names_the_missing_runtime_and_how_to_get_it(monkeypatch, tmp_path):
    monkeypatch.delenv("OPENNI2_REDIST", raising=False)
    monkeypatch.setattr(devices, "LIB_DIRS", [str(tmp_path)])
    reason = OniSource.availability()
    assert reason is not None and "libOpenNI2.so" in reason and "apt-get install libopenni2-0" in reason
    (tmp_path / "libOpenNI2.so.0").write_bytes(b"")  # a library without its drivers folder
    assert "libOniFile.so" in OniSource.availability()
    with pytest.raises(UserError, match="source 'oni': .*libOniFile"):
        OniSource(OniOptions(path=str(tmp_path / "x.oni"))).open()


def test_the_bindings_get_an_unversioned_library_beside_the_runtimes_drivers(tmp_path, monkeypatch):
    runtime = tmp_path / "lib"
    (runtime / "OpenNI2" / "Drivers").mkdir(parents=True)
    (runtime / "libOpenNI2.so.0").write_bytes(b"\x7fELF")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    shim = devices.bindings_dir(runtime / "libOpenNI2.so.0")
    assert (shim / "libOpenNI2.so").resolve() == runtime / "libOpenNI2.so.0"
    assert (shim / "OpenNI2" / "Drivers").resolve() == runtime / "OpenNI2" / "Drivers"
    assert devices.bindings_dir(runtime / "libOpenNI2.so.0") == shim  # idempotent
    (runtime / "libOpenNI2.so").write_bytes(b"\x7fELF")
    assert devices.bindings_dir(runtime / "libOpenNI2.so") == runtime  # unversioned: used as it is


@needs_runtime
def test_a_file_that_is_not_a_recording_is_refused(tmp_path):
    bad = tmp_path / "bad.oni"
    bad.write_bytes(b"not an oni file at all")
    with pytest.raises(UserError, match="OpenNI2 cannot open it"):
        OniSource(OniOptions(path=str(bad))).open()
    with pytest.raises(UserError, match="no such .oni file"):
        OniSource(OniOptions(path=str(tmp_path / "missing.oni"))).open()


@needs_runtime
def test_a_recording_made_by_openni2_opens_and_an_undecodable_one_fails_clearly(tmp_path):
    path = tmp_path / "dummy.oni"
    made = subprocess.run([sys.executable, "-c", RECORD_DUMMY, str(path)], capture_output=True, timeout=60,
                          cwd=Path(__file__).resolve().parents[2])
    if not path.exists() or path.stat().st_size == 0:
        pytest.skip(f"OpenNI2's Dummy device could not record here: {made.stderr.decode()[-300:]}")
    source = OniSource(OniOptions(path=str(path)))
    source.open()
    try:
        assert (source.width, source.height) == (320, 240) and 0 < source.frames <= 10 and source.fps == 30
        start = time.monotonic()
        with pytest.raises(UserError, match=r"delivered no depth frame for 2 s"):
            source.read()
        assert time.monotonic() - start < 10
    finally:
        source.close()


def play(**options) -> tuple[OniSource, list, float]:
    source = OniSource(OniOptions(path=str(TAKE), **options))
    source.open()
    start = time.monotonic()
    try:
        frames = list(iter(source.read, None))
    finally:
        source.close()
    return source, frames, time.monotonic() - start


@needs_runtime
def test_the_real_take_plays_every_stored_value_as_millimetres():
    take = read_oni(TAKE)
    source, frames, _ = play(realtime=False)
    assert take.codec == "16zT" and take.size == (640, 480) == (source.width, source.height)
    assert [f.frame_id for f in frames] == [f.number for f in take.frames] == list(range(1, 17))  # none skipped
    stamps = np.array([f.timestamp_us for f in take.frames])
    assert [f.timestamp for f in frames] == pytest.approx((stamps - stamps[0]) / 1e6, abs=1e-6)
    for i, frame in enumerate(frames):
        assert np.array_equal(frame.data, take.depth(i))  # the file's stored values, bit for bit
    assert [frames[-1].data[v, u] for v, u in ((240, 320), (100, 100), (400, 200), (300, 420))] == [937, 3129, 1287, 948]
    # the unit: the camera stored depth values (OutputFormat 1, not shifts), at most 10000 (mm), and
    # every value is an entry of its own shift-to-millimetre table (S2D) written beside them
    assert take.properties["OutputFormat"] == 1 and take.properties["MaxDepthValue"] == 10000
    s2d = np.frombuffer(take.properties["S2D"], "<u2")
    assert all(np.isin(np.unique(f.data), s2d).all() for f in frames)
    seen, person = frames[-1].data[frames[-1].data > 0], frames[-1].data[250:450, 300:420]
    assert 700 < np.percentile(seen, 5) and np.percentile(seen, 99) < 4000  # a room a few metres deep
    assert 800 < np.median(person) < 1000  # the person stands about 0.9 m away
    h_fov, v_fov = np.degrees(np.frombuffer(take.properties["xnFOV"], "<f8"))
    expected = Intrinsics.from_fov(640, 480, h_fov, v_fov).as_list()  # OpenNI2 hands the FOV on as float32
    assert source.intrinsics.as_list() == pytest.approx(expected, rel=1e-6) and source.mirrored is True


@needs_runtime
def test_the_real_take_is_paced_by_openni2_unless_realtime_is_off():
    _, paced, seconds = play(speed=4)
    assert seconds >= 0.8 * 1.735 / 4 and 0 < len(paced) <= 16  # OpenNI2's player keeps the recorded pace
    assert [f.frame_id for f in paced] == sorted({f.frame_id for f in paced})


@needs_runtime
def test_the_open_engine_finds_no_raised_hand_in_the_real_take():
    """A person walks in, bent forward, and stands, arms down (its ATTRIBUTION.md). While bent
    forward (the 3rd to 5th frames) the head is 200+ mm beside the spine: looked for above the
    spine only, its far side was taken for a raised hand, level with the camera and held to the
    8th frame. The head is looked for above the user's top when that is a head-wide crest cut by
    the spine column's edge; so in every frame any hand found hangs at chest height or below, a
    quarter metre and more under the camera's axis (the person's head is level with it)."""
    seen = hands_in(OniSource(OniOptions(path=str(TAKE), realtime=False)))
    assert len(seen) == 16
    assert all(h.position[1] < -250 for hands in seen for h in hands)
    assert any(seen[8:])  # the arms are found once the person stands


@needs_runtime
def test_the_open_engine_makes_no_person_of_the_furniture_in_the_real_take():
    """Low in the picture, 2.6 m away, the take shows a surface cut by the picture's bottom (0.6 m
    wide, 0.3 m tall in the picture but 0.1 m in the room: a floor piece or a low shelf seen from
    above). A rule letting anything the bottom cuts be a person from 300 mm in the picture made it
    one (and found the person who walks in before their shoulders were in view). At the picture's
    left edge, 2.5 m away, a shelf 0.7 m tall stands over 1.1 m without a reading (a dark cabinet):
    person-sized, it was a second user in every frame. And no floor is in view: a plane through
    the camera, fitted to the picture's bottom rows, cut the person in half at the hips. The one
    person is found from the frame their head and shoulders are in view (the third) on."""
    source, frames, _ = play(realtime=False)
    segmenter = Segmenter(SegmentationOptions())
    people = [segmenter.people(frame) for frame in frames]
    assert all(p.centre[1] > -700 and p.centre[2] < 1300 for found in people for p in found)
    assert [len(found) for found in people] == [0] * 2 + [1] * 14
    assert all(found[0].segment.mask[-1].any() for found in people[2:])  # down to the picture's bottom


@needs_runtime
def test_issv_run_plays_the_real_take_frame_by_frame(tmp_path):
    prof = write_profile(tmp_path / "p.toml", {"name": "oni", "path": str(TAKE), "realtime": False},
                         {"name": "openiss"})
    metrics = tmp_path / "m.json"
    assert issv(["run", str(prof), "--headless", "--no-reload", "--metrics-json", str(metrics)]) == 0
    assert json.loads(metrics.read_text())["frames"] == 16
