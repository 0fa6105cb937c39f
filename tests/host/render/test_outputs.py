"""`issv run PROFILE --size WxH --out FILE.mp4 --snapshot FILE.png` headless: the files are really
written, OpenCV reads them back at the asked size, and a broken output is one clear error."""
import cv2
import pytest

from host.cli import main
from tests.host.render.stage import depth_view_profile, requires_gl

def profile(tmp_path, hud=False):
    return depth_view_profile(tmp_path, frames=20, mode="headless", hud=hud)


@requires_gl
def test_video_and_snapshot_are_written_at_the_asked_size(tmp_path):
    video, png = tmp_path / "show.mp4", tmp_path / "last.png"
    code = main(["run", str(profile(tmp_path, hud=True)), "--size", "256x144", "--out", str(video),
                 "--snapshot", str(png)])
    assert code == 0
    image = cv2.imread(str(png))
    assert image is not None and image.shape == (144, 256, 3)
    assert image[60:100, 100:200].max() > 100  # the depth view's wall and box are there
    cap = cv2.VideoCapture(str(video))
    try:
        assert cap.get(cv2.CAP_PROP_FRAME_WIDTH) == 256 and cap.get(cv2.CAP_PROP_FRAME_HEIGHT) == 144
        ok, frame = cap.read()
        assert ok and frame.shape == (144, 256, 3) and frame.max() > 100
        count = 1
        while cap.read()[0]:
            count += 1
        assert count >= 10  # 20 frames at 30 Hz played in real time: about 0.67 s of video
    finally:
        cap.release()


@requires_gl
def test_a_snapshot_into_a_missing_folder_is_one_clear_error(tmp_path, capsys):
    code = main(["run", str(profile(tmp_path)), "--snapshot", str(tmp_path / "nope" / "x.png")])
    assert code == 1
    err = capsys.readouterr().err
    assert "nope" in err and "does not exist" in err and "Traceback" not in err


@requires_gl
@pytest.mark.parametrize("keystone", ["[[0, 0], [1, 0], [1, 1]]", "[[0, 0], [1, 1], [1, 0], [0, 1]]"])
def test_a_bad_keystone_names_the_key(tmp_path, capsys, keystone):
    path = profile(tmp_path)
    path.write_text(path.read_text() + f"keystone = {keystone}\n")
    assert main(["run", str(path)]) == 1
    assert "output.keystone" in capsys.readouterr().err
