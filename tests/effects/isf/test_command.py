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
