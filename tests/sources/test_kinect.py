"""`kinect` through libfreenect's own fakenect replay library: the code path of a live Kinect.

Each test runs a child process under Debian's `fakenect` wrapper (it puts libfreenect's fakenect
library first on LD_LIBRARY_PATH and sets FAKENECT_PATH), as an artist replaying a dump would.
The child plays the dump through the `kinect` source; the frames must equal what the `fakenect`
source reads from the same files (millimetres from the same disparities, bit for bit).
"""
from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from host import DeviceInfo
from host.cli import main as issv
from sources import usb
from sources.fakenect import FakenectOptions, FakenectSource, read_index
from sources.kinect import KinectOptions, KinectSource
from tests.sources.test_fakenect import dump_folder

ROOT = Path(__file__).resolve().parents[2]
needs_fakenect = pytest.mark.skipif(
    shutil.which("fakenect") is None or KinectSource.availability() is not None,
    reason=f"libfreenect's fakenect (Debian libfreenect-bin) or the kinect extra is missing: "
           f"{KinectSource.availability()}")

PLAY = """
import json, sys
import numpy as np
from sources.kinect import KinectOptions, KinectSource
source = KinectSource(KinectOptions())
source.open()
frames = []
while (frame := source.read()) is not None:
    frames.append(frame)
source.close()
np.savez(sys.argv[1], depth=np.stack([f.data for f in frames]), times=[f.timestamp for f in frames])
print(json.dumps({"health": source.health(), "dropped": source.dropped,
                  "devices": [d.model for d in KinectSource.devices()]}))
"""

TRACK = """
import json
from backends.engine.backend import OpenISSBackend
from sources.kinect import KinectOptions, KinectSource
with OpenISSBackend(KinectSource(KinectOptions())) as backend:
    while (frame := backend.update()) is not None:
        print(json.dumps([frame.depth.timestamp, [h.position for h in frame.hands if h.in_view]]))
"""


def under_fakenect(dump: Path, script: str, *args: str) -> str:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    done = subprocess.run(["fakenect", str(dump), sys.executable, "-c", script, *args], capture_output=True,
                          text=True, timeout=120, env=env, cwd=ROOT)
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout


def direct(dump: Path) -> np.ndarray:
    source = FakenectSource(FakenectOptions(path=str(dump)))
    source.open()
    return np.stack([f.data for f in iter(source.read, None)])


def check_replay(dump: Path, tmp_path: Path) -> tuple[np.lib.npyio.NpzFile, list[int]]:
    """Every frame the kinect source delivered equals the file it came from, bit for bit. The
    replay runs in real time, so a loaded machine may miss one: then it must count it as dropped."""
    report = json.loads(under_fakenect(dump, PLAY, str(tmp_path / "played.npz")).splitlines()[-1])
    played = np.load(tmp_path / "played.npz")
    stamps = np.array([int(e.path.stem.rsplit("-", 1)[1]) for e in read_index(dump)], np.float64)
    times = (stamps - stamps[0]) / 60e6  # the device's 60 MHz clock
    for first in range(len(times)):  # the source's clock starts at the first frame it delivered
        index = [int(np.argmin(np.abs(times - times[first] - t))) for t in played["times"]]
        if np.allclose(times[index] - times[first], played["times"], atol=1e-6):
            break
    assert index[0] == first and index == sorted(set(index))
    expected = direct(dump)
    assert all(np.array_equal(frame, expected[i]) for frame, i in zip(played["depth"], index))
    assert len(index) >= 0.9 * len(expected) and report["dropped"] == len(expected) - len(index)
    assert report["devices"] == ["fakenect replay"] and f"dropped {report['dropped']}" in report["health"]
    return played, index


@needs_fakenect
def test_a_dump_plays_through_libfreenect_exactly_as_its_files_say(tmp_path):
    played, _ = check_replay(dump_folder(tmp_path / "dump", frames=8), tmp_path)
    assert played["depth"].shape[1:] == (480, 640) and played["depth"][0, 200, 250] == pytest.approx(1500, rel=0.01)


@needs_fakenect
def test_registered_depth_is_refused_under_fakenect_with_a_reason(tmp_path):
    script = ("from sources.kinect import *\ntry:\n    KinectSource(KinectOptions(registered=True)).open()\n"
              "except Exception as e:\n    print(e)\n")
    assert "needs a live Kinect" in under_fakenect(dump_folder(tmp_path / "dump", frames=2), script)


def real_dump() -> Path:
    data = os.environ.get("ISSV_DATA")
    if not data:
        pytest.skip("ISSV_DATA is not set: the real Kinect dump is not here")
    return Path(data) / "real-depth" / "kinect-desk-hand"


@needs_fakenect
def test_the_real_desk_dump_plays_bit_exact_through_libfreenect(tmp_path):
    played, index = check_replay(real_dump(), tmp_path)
    assert len(read_index(real_dump())) == 98
    first = read_index(real_dump())[index[0]].path.read_bytes()
    raw = np.frombuffer(first[first.index(b"\n") + 1:], "<u2").reshape(480, 640)  # the file's own disparities
    for v, u in ((240, 320), (100, 500), (400, 150), (300, 400)):
        d = int(raw[v, u])
        assert played["depth"][0][v, u] == (0 if d == 2047 else round(123.6 * math.tan(d / 2842.5 + 1.1863)))
    person = played["depth"][0][played["depth"][0] > 0]
    assert 500 < np.percentile(person, 5) < 700  # seated about 0.6 m away (its README)


@needs_fakenect
def test_the_open_engine_finds_the_raised_hand_in_the_real_dump():
    lines = [json.loads(line) for line in under_fakenect(real_dump(), TRACK).splitlines() if line.startswith("[")]
    raised = {round(t, 1): any(p[1] > 0 for p in hands) for t, hands in lines}  # a hand above the camera's axis
    before = [r for t, r in raised.items() if t < 1.0]
    during = [r for t, r in raised.items() if 1.4 <= t <= 2.7]
    assert len(lines) >= 90 and not any(before) and sum(during) >= 0.8 * len(during)


@pytest.fixture
def kinect_on_usb(tmp_path, monkeypatch) -> Path:
    """A sysfs tree as Linux lays it out for a Kinect camera (no Kinect is plugged in here)."""
    monkeypatch.delenv("FAKENECT_PATH", raising=False)
    cam = tmp_path / "1-2"
    cam.mkdir()
    for name, value in {"idVendor": "045e", "idProduct": "02ae", "product": "Xbox NUI Camera",
                        "serial": "A00366A08453045A", "bcdDevice": "010b", "busnum": "1", "devnum": "7"}.items():
        (cam / name).write_text(value + "\n")
    monkeypatch.setattr(usb, "SYSFS", tmp_path)
    monkeypatch.setattr(usb, "DEVFS", tmp_path / "dev")
    return tmp_path


def test_devices_name_a_plugged_in_kinect_and_the_udev_rule_it_needs(kinect_on_usb):
    tmp_path = kinect_on_usb
    [device] = KinectSource.devices()
    assert (device.model, device.serial, device.firmware) == ("Xbox NUI Camera", "A00366A08453045A", "010b")
    assert 'ATTR{idVendor}=="045e", ATTR{idProduct}=="02ae", MODE="0666"' in device.problem
    assert str(tmp_path / "dev" / "001" / "007") in device.problem
    node = tmp_path / "dev" / "001" / "007"
    node.parent.mkdir(parents=True)
    node.write_bytes(b"")
    assert KinectSource.devices() == [DeviceInfo("Xbox NUI Camera", "A00366A08453045A", "010b",
                                                 device.modes, None)]


@pytest.mark.skipif(KinectSource.availability() is not None, reason=str(KinectSource.availability()))
def test_without_a_kinect_the_source_says_to_plug_one_in(monkeypatch):
    monkeypatch.delenv("FAKENECT_PATH", raising=False)
    from host.errors import UserError
    with pytest.raises(UserError, match=r"no Kinect v1 at index 0 \(0 found\): plug one in"):
        KinectSource(KinectOptions()).open()


@pytest.mark.skipif(KinectSource.availability() is not None, reason=str(KinectSource.availability()))
def test_issv_list_names_the_kinect_and_what_to_do(kinect_on_usb, capsys):
    assert issv(["list", "--json"]) == 0
    sources = {s["name"]: s for s in json.loads(capsys.readouterr().out)["sources"]}
    [device] = sources["kinect"]["devices"]
    assert device["serial"] == "A00366A08453045A" and "udev rule" in device["problem"]
    assert "devices" not in sources["clip"]  # files have no devices
    assert issv(["list"]) == 0
    table = capsys.readouterr().out
    assert "Xbox NUI Camera" in table and "A00366A08453045A" in table
