"""fakenect dump folders, written here byte for byte as libfreenect's fakenect-record writes them."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from host import Intrinsics
from host.cli import main as issv
from host.errors import UserError
from sources.fakenect import FakenectOptions, FakenectSource
from tests.recordings import write_profile

W, H = 640, 480
WALL_MM, PERFORMER_MM = 3000.0, 1500.0
T0 = 1294873002.535302


def disparity(mm: float) -> int:
    """Inverse of the Kinect v1 fit, as the sensor would have reported that distance."""
    return round((math.atan(mm / 123.6) - 1.1863) * 2842.5)


def dump_folder(folder: Path, frames: int = 6, fps: float = 30.0) -> Path:
    """What fakenect-record writes: INDEX.txt, d-*.pgm (header line + little-endian 11-bit), r-*.ppm, a-*.dump."""
    folder.mkdir()
    lines = []
    for i in range(frames):
        t = T0 + i / fps
        raw = np.full((H, W), disparity(WALL_MM), "<u2")
        raw[100:300, 200 + 10 * i: 300 + 10 * i] = disparity(PERFORMER_MM)
        raw[:20, :] = 2047  # no reading
        for kind, ext, payload in (("d", "pgm", b"P5 640 480 65535\n" + raw.tobytes()),
                                   ("r", "ppm", b"P6 640 480 255\n" + bytes(W * H * 3)),
                                   ("a", "dump", bytes(20))):
            name = f"{kind}-{t:f}-{1000 + i * 1001}.{ext}"
            (folder / name).write_bytes(payload)
            lines.append(name)
    (folder / "INDEX.txt").write_text("\n".join(lines) + "\n")
    return folder


def test_a_dump_folder_plays_as_millimetres(tmp_path):
    source = FakenectSource(FakenectOptions(path=str(dump_folder(tmp_path / "dump"))))
    source.open()
    frames = []
    while (frame := source.read()) is not None:
        frames.append(frame)
    assert len(frames) == 6 and source.fps == pytest.approx(30.0, rel=1e-3)
    assert source.intrinsics == Intrinsics.from_fov(640, 480, 57, 43)
    assert [f.timestamp for f in frames] == pytest.approx([i / 30 for i in range(6)], abs=1e-5)
    first = frames[0].data
    assert first[:20].max() == 0  # 2047: no reading
    assert first[400, 600] == pytest.approx(WALL_MM, rel=0.01)  # one disparity step is under 1 % here
    assert first[200, 250] == pytest.approx(PERFORMER_MM, rel=0.01)
    assert frames[3].data[200, 200 + 30] == first[200, 250] and not frames[0].mirrored


def test_issv_run_plays_a_dump_folder(tmp_path):
    folder = dump_folder(tmp_path / "dump", frames=10)
    prof = write_profile(tmp_path / "p.toml", {"name": "fakenect", "path": str(folder), "loop": True})
    metrics = tmp_path / "m.json"
    assert issv(["run", str(prof), "--headless", "--fast", "--no-reload", "--frames", "25",
                 "--metrics-json", str(metrics)]) == 0
    assert json.loads(metrics.read_text())["frames"] == 25  # looped past the folder's 10 frames


@pytest.mark.parametrize("damage, message", [
    (lambda f: (f / "INDEX.txt").unlink(), "not a fakenect dump folder"),
    (lambda f: (f / "INDEX.txt").write_text("depth0001.pgm\n"), r"INDEX.txt:1: expected a depth file name"),
    (lambda f: next(f.glob("d-*.pgm")).write_bytes(b"P5 640 480 65535\n" + bytes(100)), "bytes of pixels"),
    (lambda f: next(f.glob("d-*.pgm")).write_bytes(b"P5 640 480 65535\n" + np.full((H, W), 3000, "<u2").tobytes()),
     "not 11-bit disparities"),
])
def test_bad_folders_say_what_is_wrong(tmp_path, damage, message):
    folder = dump_folder(tmp_path / "dump", frames=1)
    damage(folder)
    source = FakenectSource(FakenectOptions(path=str(folder)))
    with pytest.raises(UserError, match=message):
        source.open()
        source.read()
