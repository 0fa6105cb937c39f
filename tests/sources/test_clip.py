import numpy as np
import pytest

from host.errors import UserError
from sources.clip import ClipSource
from tests.conftest import real_data, write_clip


def frames_of(path, **options):
    source = ClipSource(ClipSource.Options(path=str(path), **options))
    source.open()
    return source


def test_a_clip_plays_its_frames_then_ends(clip):
    source = frames_of(clip)
    frames = []
    while (f := source.read()) is not None:
        frames.append(f)
    assert len(frames) == 30 and source.fps == pytest.approx(30.0)
    assert [f.frame_id for f in frames] == list(range(30))
    assert not frames[3].data.flags.writeable and frames[3].data[80, 9] == 2000


def test_looping_keeps_time_moving_forwards(tmp_path):
    source = frames_of(write_clip(tmp_path / "c.npz", frames=5), loop=True)
    stamps = [source.read().timestamp for _ in range(12)]
    assert np.all(np.diff(stamps) > 0) and stamps[5] == pytest.approx(5 / 30)


def test_corrupt_and_incomplete_clips_say_what_is_wrong(tmp_path):
    broken = tmp_path / "broken.npz"
    broken.write_bytes(b"PK\x03\x04 not really a zip")
    with pytest.raises(UserError, match="broken.npz: not a readable .npz depth clip"):
        frames_of(broken)
    noise = tmp_path / "noise.npz"
    noise.write_bytes(bytes(range(256)) * 4)
    with pytest.raises(UserError, match=r"noise.npz: not a readable .npz depth clip \(not a zip archive") as error:
        frames_of(noise)
    assert "pickle" not in str(error.value)
    partial = tmp_path / "partial.npz"
    np.savez(partial, depth=np.zeros((2, 4, 4), np.uint16))
    with pytest.raises(UserError, match="partial.npz: depth clip has no `timestamps` array"):
        frames_of(partial)


def test_the_real_clips_play_with_their_truth():
    path = sorted(real_data("utd-mhad-dev", "clips").glob("*swipe_left*.npz"))[0]
    source = frames_of(path)
    first = source.read()
    assert (first.width, first.height) == (320, 240) and first.mirrored
    assert source.intrinsics.fx == pytest.approx(285.63)
    assert {s.value for s in first.truth.hands} == {"left", "right"}
    assert {"head", "torso"} <= set(first.truth.body)
