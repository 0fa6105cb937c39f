"""`depth-images`: 16-bit PNG/TIFF folders and TUM-style lists, and real SR305 frames.

The SR305 frames in tests/data/realsense-sr305-hands are four of Ladislav Ondris's (MIT, see the
folder's ATTRIBUTION.md); the whole sequences are read from ISSV_DATA when it is set. Raw pixel
values are decoded with Pillow, a different PNG decoder from the source's OpenCV.
"""
from __future__ import annotations

import json
import os
from pathlib import Path

import cv2
import numpy as np
import pytest
from PIL import Image

from backends.engine.backend import OpenISSBackend
from host import Intrinsics, Side, Source
from host.cli import main as issv
from host.errors import UserError
from sources.depth_images import DepthImagesOptions, DepthImagesSource, natural_key
from tests.recordings import write_profile

SR305 = Path(__file__).resolve().parents[1] / "data" / "realsense-sr305-hands"
SR305_INTRINSICS = Intrinsics(476.007, 476.007, 313.683, 242.755)


def play(path: Path, **options) -> tuple[DepthImagesSource, list]:
    source = DepthImagesSource(DepthImagesOptions(path=str(path), **options))
    source.open()
    frames = []
    while (frame := source.read()) is not None:
        frames.append(frame)
    return source, frames


def counts(i: int, size=(64, 48)) -> np.ndarray:
    """A frame of raw counts that says which frame it is (so order is checked)."""
    raw = np.full(size[::-1], 8000 + i, np.uint16)
    raw[:4] = 0
    return raw


def write_folder(folder: Path, n: int, suffix: str = ".png") -> Path:
    folder.mkdir()
    for i in range(n):
        assert cv2.imwrite(str(folder / f"{i * 10}{suffix}"), counts(i))  # 0, 10, ..., 100: natural order
    return folder


@pytest.mark.parametrize("suffix", [".png", ".tif"])
def test_a_folder_plays_in_natural_order_with_the_units_of_a_json_beside_it(tmp_path, suffix):
    folder = write_folder(tmp_path / "depth", 11, suffix)
    (folder / "camera.json").write_text(json.dumps({"depth_unit_mm": 0.25, "intrinsics": [50, 51, 32, 24],
                                                    "fps": 15}))
    source, frames = play(folder)
    assert [f.data[10, 10] for f in frames] == [round((8000 + i) * 0.25) for i in range(11)]
    assert all(f.data[:4].max() == 0 for f in frames)  # 0 stays "no reading"
    assert source.intrinsics == Intrinsics(50, 51, 32, 24) and source.fps == 15
    assert [f.timestamp for f in frames] == pytest.approx([i / 15 for i in range(11)])
    assert not frames[0].mirrored


def test_the_profile_overrides_the_description_and_loops_forward_in_time(tmp_path):
    folder = write_folder(tmp_path / "depth", 3)
    (tmp_path / "readme.txt").write_text("depth unit = 0.5 mm\nfocal length = 40\nprincipal point = (30, 20)\n")
    source, frames = play(folder)  # the readme in the parent folder
    assert source.depth_unit_mm == 0.5 and source.intrinsics == Intrinsics(40, 40, 30, 20)
    assert frames[2].data[10, 10] == round(8002 * 0.5)
    source = DepthImagesSource(DepthImagesOptions(path=str(folder), depth_unit_mm=1, intrinsics=[1, 2, 3, 4],
                                                  fps=10, loop=True))
    source.open()
    looped = [source.read() for _ in range(7)]
    assert looped[6].data[10, 10] == 8000 and source.intrinsics == Intrinsics(1, 2, 3, 4)
    assert [f.timestamp for f in looped] == pytest.approx([i / 10 for i in range(7)])


def test_a_tum_style_list_gives_the_order_and_the_times(tmp_path):
    write_folder(tmp_path / "depth", 4)
    listing = tmp_path / "depth.txt"
    listing.write_text("# depth maps\n# timestamp filename\n"
                       "1305031102.160407 depth/30.png\n1305031102.194330 depth/0.png\n"
                       "1305031102.226738 depth/20.png\n")
    source, frames = play(listing)
    assert [f.data[10, 10] for f in frames] == [8003, 8000, 8002]
    assert [f.timestamp for f in frames] == pytest.approx([0, 0.033923, 0.066331], abs=1e-6)
    assert source.fps == pytest.approx(1 / 0.0331655, rel=1e-3)


def test_names_sort_as_numbers():
    assert sorted(["110.png", "30.png", "frame_2.png", "frame_10.png"], key=natural_key) == \
        ["30.png", "110.png", "frame_2.png", "frame_10.png"]


@pytest.mark.parametrize("make, message", [
    (lambda d: None, "no depth images"),
    (lambda d: cv2.imwrite(str(d / "0.png"), np.zeros((48, 64, 3), np.uint8)), "3-channel uint8 image"),
    (lambda d: (d / "0.png").write_bytes(b"not a png"), "not a readable PNG or TIFF"),
    (lambda d: (cv2.imwrite(str(d / "0.png"), counts(0)), cv2.imwrite(str(d / "1.png"), counts(1, (32, 24)))),
     "one folder, one size"),
])
def test_bad_folders_say_which_file_and_what_to_do(tmp_path, make, message):
    folder = tmp_path / "depth"
    folder.mkdir()
    make(folder)
    with pytest.raises(UserError, match=message):
        play(folder)


@pytest.mark.parametrize("content, message", [
    ("{depth_unit_mm: 0.125", "camera.json: not valid JSON"),
    ('{"intrinsics": [1, 2, 3]}', r"camera.json: intrinsics must be \[fx, fy, cx, cy\]"),
    ('{"depth_unit_mm": "0.125 mm"}', "camera.json: depth_unit_mm must be a number"),
])
def test_a_broken_json_description_names_the_file_and_field(tmp_path, content, message):
    folder = write_folder(tmp_path / "depth", 1)
    (folder / "camera.json").write_text(content)
    with pytest.raises(UserError, match=message):
        play(folder)


def test_a_bad_list_line_names_the_line(tmp_path):
    listing = tmp_path / "depth.txt"
    listing.write_text("1.0 a.png\n2.0\n")
    with pytest.raises(UserError, match=r"depth.txt:2: expected `timestamp filename`"):
        play(listing)
    with pytest.raises(UserError, match="no such folder or image list"):
        play(tmp_path / "missing")


def test_bad_intrinsics_in_the_profile_are_refused():
    with pytest.raises(ValueError, match=r"\[fx, fy, cx, cy\]"):
        DepthImagesOptions(path="x", intrinsics=[1, 2, 3])


def test_real_sr305_frames_are_millimetres_of_the_raw_counts(tmp_path):
    source, frames = play(SR305 / "20210326-231615")
    assert source.depth_unit_mm == 0.125 and source.intrinsics == SR305_INTRINSICS
    assert len(frames) == 4 and (source.width, source.height) == (640, 480)
    assert [frames[0].data[v, u] for v, u in ((163, 383), (310, 499), (479, 579))] == [730, 784, 625]  # 5842, 6272, 5003
    for frame, path in zip(frames, sorted((SR305 / "20210326-231615").glob("*.png"), key=lambda p: int(p.stem))):
        raw = np.array(Image.open(path))
        assert 0.15 < (raw > 0).mean() and np.array_equal(frame.data, np.round(raw * 0.125).astype(np.uint16))
        person = frame.data[raw > 0]
        assert 450 < np.percentile(person, 5) and np.percentile(person, 95) < 1200  # 0.5-1.1 m (its README)


def hands_in(source: Source) -> list[tuple]:
    """The hands the open engine reports in every frame of a real recording, each checked to be
    where the depth image has something that near (a measured hand, not a guess)."""
    backend = OpenISSBackend(source)
    seen = []
    with backend:
        while (frame := backend.update()) is not None:
            held = {h.position for h in seen[-1]} if seen else set()
            seen.append(tuple(h for h in frame.hands if h.in_view))
            for h in seen[-1]:
                if h.position in held:
                    continue  # held where it was last seen (a dropout), not measured in this frame
                u, v, z = frame.depth.world_to_depth(h.position)
                patch = frame.depth.data[int(v) - 15: int(v) + 16, int(u) - 15: int(u) + 16]
                assert np.abs(patch[patch > 0].astype(float) - z).min() < 30
    return seen


def test_the_open_engine_finds_the_raised_hand_in_real_sr305_frames():
    seen = hands_in(DepthImagesSource(DepthImagesOptions(path=str(SR305 / "20210326-231615"))))
    assert all(len(hands) == 1 and hands[0].side is Side.RIGHT for hands in seen)  # annotated: right hand


@pytest.mark.parametrize("sequence", ["20210326-230536", "20210326-231615"])
def test_whole_sr305_sequences_give_the_raised_right_hand(sequence):
    data = os.environ.get("ISSV_DATA")
    if not data:
        pytest.skip("ISSV_DATA is not set: the real-depth recordings are not here")
    path = Path(data) / "real-depth" / "realsense-sr305-hands" / sequence
    seen = hands_in(DepthImagesSource(DepthImagesOptions(path=str(path))))
    with_hand = [hands for hands in seen if hands]
    assert len(with_hand) >= len(seen) - 1  # the first frame may only start the track
    assert all(h.side is Side.RIGHT for hands in with_hand for h in hands)


def test_issv_run_plays_a_depth_image_folder(tmp_path):
    prof = write_profile(tmp_path / "p.toml", {"name": "depth-images", "path": str(SR305 / "20210326-231615"),
                                               "loop": True}, {"name": "openiss"})
    metrics = tmp_path / "m.json"
    assert issv(["run", str(prof), "--headless", "--fast", "--no-reload", "--frames", "10",
                 "--metrics-json", str(metrics)]) == 0
    assert json.loads(metrics.read_text())["frames"] == 10
