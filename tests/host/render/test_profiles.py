"""The shipped stage profiles validate and play headless: the thesis' sample application and the
ISSv2-like stage show, on the synthetic performer and the open engine, with the HUD on."""
from pathlib import Path

import cv2
import pytest

from host.cli import main
from tests.host.render.stage import requires_gl

PROFILES = Path(__file__).resolve().parents[3] / "profiles"


@requires_gl
@pytest.mark.parametrize("name", ["sample-app", "stage"])
def test_profile_plays_headless_and_shows_something(tmp_path, name, capsys):
    png = tmp_path / f"{name}.png"
    code = main(["run", str(PROFILES / f"{name}.toml"), "--headless", "--size", "320x180", "--seconds", "1.5",
                 "--snapshot", str(png)])
    assert code == 0
    image = cv2.imread(str(png))
    assert image.shape == (180, 320, 3)
    assert image[60:, :].max() > 60  # the performer (depth view or contours) is on stage
    hud = image[4:30, 6:120]
    assert (hud.min(axis=2) > 200).sum() > 20  # white HUD text in the top-left corner
    assert "Traceback" not in capsys.readouterr().err
