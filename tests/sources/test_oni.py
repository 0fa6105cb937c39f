"""`.oni` files through the real OpenNI2 runtime (Debian's libopenni2-0 + the `openni` bindings).

No real camera recording can be fetched here (no network beyond package registries), so the file
is made by OpenNI2 itself: its own Recorder, recording its bundled `Dummy` test device. OpenNI2's
file player opens such a file (streams, frame count, video mode) but delivers none of its frames
on this machine, so the frame test checks the source reports that clearly instead of hanging.
"""
from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import pytest

from host import devices
from host.errors import UserError
from sources.oni import OniOptions, OniSource

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
