"""`issv isf FILE...`: a real process renders shipped ISF shaders headless and reports each one."""
import json
import os
import random
import subprocess
import sys
from pathlib import Path

import cv2
import pytest

from tests.host.render.stage import requires_gl

SHADERS = Path(__file__).resolve().parents[3] / "effects" / "shaders"
KEYS = ["file", "ok", "error", "passes", "kind", "mean", "std"]


def issv_isf(*args):
    return subprocess.run([sys.executable, "-m", "host", "isf", *map(str, args)], capture_output=True, text=True,
                          timeout=600)


@requires_gl
def test_shipped_shaders_play_and_a_broken_one_names_file_and_line(tmp_path):
    broken = tmp_path / "broken.fs"
    broken.write_text('/*{\n  "INPUTS": []\n}*/\nvoid main() {\n    gl_FragColor = vec4(1.0)\n}\n')
    files = [SHADERS / "vidvox" / name for name in ("Motion Heat Map.fs", "3d Rotate.fs", "Ripple Transition.fs",
                                                    "Audio Waveform Shape.fs", "Night Vision.fs")]
    run = issv_isf(*files, broken, "--size", "96x54", "--frames", "3", "--json", "--snapshot-dir", tmp_path / "png")
    assert run.returncode == 1, run.stderr  # one file failed
    results = [json.loads(line) for line in run.stdout.splitlines()]
    assert [list(r) for r in results] == [KEYS] * 6
    by_name = {Path(r["file"]).name: r for r in results}
    heat = by_name["Motion Heat Map.fs"]
    assert heat["ok"] and heat["passes"] == 3 and heat["kind"] == "filter" and heat["std"] > 0.002
    assert by_name["Ripple Transition.fs"]["kind"] == "transition"
    assert by_name["Audio Waveform Shape.fs"]["std"] > 0.002  # the test tone is drawn
    bad = by_name["broken.fs"]
    assert not bad["ok"] and bad["error"].startswith(f"{broken}:6: error: syntax error")
    assert all(r["ok"] for r in results[:5])
    png = cv2.imread(str(tmp_path / "png" / "Night Vision.png"))
    assert png.shape == (54, 96, 3) and png.std() > 1
    assert "5/6 ok" in run.stderr


ENDLESS = """/*{"INPUTS": [{"NAME": "k", "TYPE": "float", "DEFAULT": 1.0}]}*/
// far more work per pixel than a frame can afford (not a nested loop: llvmpipe caps those)
float spin(float x) {
    for (int i = 0; i < 60000; i++)
        x = sin(x * k + float(i));
    return x;
}
void main() {
    float x = isf_FragNormCoord.x;
    x = spin(x); x = spin(x); x = spin(x); x = spin(x); x = spin(x); x = spin(x); x = spin(x); x = spin(x);
    x = spin(x); x = spin(x); x = spin(x); x = spin(x); x = spin(x); x = spin(x); x = spin(x); x = spin(x);
    gl_FragColor = vec4(x, 0.0, 0.0, 1.0);
}
"""


@requires_gl
def test_a_shader_that_does_not_finish_in_time_is_not_ok_and_the_next_file_runs(tmp_path):
    endless = tmp_path / "endless.fs"
    endless.write_text(ENDLESS)
    run = issv_isf(endless, SHADERS / "vidvox" / "Night Vision.fs", "--size", "64x36", "--frames", "2", "--json",
                   "--timeout", "3")
    assert run.returncode == 1, run.stderr
    slow, good = (json.loads(line) for line in run.stdout.splitlines())
    assert list(slow) == KEYS and not slow["ok"] and slow["kind"] == "generator" and slow["passes"] == 1
    assert slow["error"] == f"{endless}: did not finish 2 frame(s) within 3 s (--timeout); skipped"
    assert good["ok"] and good["std"] > 0.002
    assert "1/2 ok" in run.stderr


def test_a_timeout_must_be_positive():
    run = issv_isf(SHADERS / "hand-glow.fs", "--timeout", "0")
    assert run.returncode == 2 and "--timeout must be more than 0 seconds" in run.stderr


def test_a_bad_size_is_refused():
    run = issv_isf(SHADERS / "hand-glow.fs", "--size", "big")
    assert run.returncode == 2 and "--size 'big': expected WxH" in run.stderr


@requires_gl
def test_the_vidvox_collection_plays(tmp_path):
    """A fixed sample of the collection (the whole of it: `issv isf .../ISF/*.fs`, see the issue's note)."""
    data = os.environ.get("ISSV_DATA")
    if not data:
        pytest.skip("set ISSV_DATA to the shared data folder (isf-files/ISF: the Vidvox ISF collection)")
    files = sorted((Path(data) / "isf-files" / "ISF").glob("*.fs"))
    sample = random.Random(22).sample(files, 30)
    run = issv_isf(*sample, "--size", "128x72", "--frames", "4", "--json")
    results = [json.loads(line) for line in run.stdout.splitlines()]
    assert len(results) == 30, run.stderr
    failed = [r["error"] for r in results if not r["ok"]]
    assert len(failed) <= 1, failed
    flat = [r["file"] for r in results if r["std"] <= 0.002]
    assert len(flat) <= 4, flat


def test_std_is_zero_for_a_frame_of_one_colour_however_saturated():
    import numpy as np

    from effects.isf.trial import colour_spread

    red = np.zeros((4, 6, 3), np.uint8)
    red[..., 0] = 255
    assert colour_spread(red) == 0.0  # np.std over all values would say 0.47
    half = red.copy()
    half[:2] = 0
    assert colour_spread(half) == pytest.approx(0.5 / np.sqrt(3), abs=1e-6)
