"""A real window (moderngl-window on pyglet) under a virtual X server: windowed at the asked size,
fullscreen at the monitor's size, a missing monitor named, and the interactive calibration driven
with a real mouse and keyboard (xdotool)."""
import os
import shutil
import subprocess
import sys
import tomllib

import cv2
import pytest

from tests.host.render.stage import depth_view_profile

pytestmark = pytest.mark.skipif(shutil.which("xvfb-run") is None,
                                reason="no virtual X server for a window test (Debian: apt-get install xvfb)")
WINDOW = {"size": [320, 200], "hud": False}

def run_in_window(tmp_path, mode, monitor=0):
    profile = depth_view_profile(tmp_path, 15, "window.toml", **WINDOW, mode=mode, monitor=monitor)
    png = tmp_path / "window.png"
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    done = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 800x600x24", sys.executable, "-m", "host.cli", "run",
                           str(profile), "--snapshot", str(png)], capture_output=True, text=True, timeout=120, env=env)
    return done, cv2.imread(str(png))


def test_a_window_shows_the_stage_at_the_profiles_size(tmp_path):
    done, image = run_in_window(tmp_path, "window")
    assert done.returncode == 0, done.stderr
    assert "rendering headless" not in done.stderr  # a real window, not the fallback
    assert image.shape == (200, 320, 3) and image.max() > 100


def test_fullscreen_takes_the_monitors_size(tmp_path):
    done, image = run_in_window(tmp_path, "fullscreen")
    assert done.returncode == 0, done.stderr
    assert image.shape == (600, 800, 3)


def test_a_monitor_that_is_not_there_is_named(tmp_path):
    done, _ = run_in_window(tmp_path, "fullscreen", monitor=3)
    assert done.returncode == 1
    assert "output.monitor: there is no monitor 3" in done.stderr


@pytest.mark.skipif(shutil.which("xdotool") is None, reason="no xdotool to drive the window (apt-get install xdotool)")
def test_interactive_calibration_drags_a_corner_and_saves_it(tmp_path):
    """`issv calibrate` in a real window: drag the top-left corner with the mouse, press Enter."""
    profile = depth_view_profile(tmp_path, 15, "cal.toml", loop=True, **WINDOW, mode="window", monitor=0)
    profile.write_text(profile.read_text() + "# keep me\n")
    script = tmp_path / "drive.sh"
    script.write_text(f"""#!/bin/bash
{sys.executable} -m host.cli calibrate {profile} &
pid=$!
for i in $(seq 50); do wid=$(xdotool search --name "issv calibrate" | head -1); [ -n "$wid" ] && break; sleep 0.2; done
sleep 1
xdotool mousemove --window $wid 2 2 mousedown 1 mousemove --window $wid 20 12 mousemove --window $wid 32 20 mouseup 1
sleep 0.5
xdotool key --window $wid Return
wait $pid
""")
    script.chmod(0o755)
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    done = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 800x600x24", str(script)], capture_output=True,
                          text=True, timeout=120, env=env)
    assert "saved output.keystone" in done.stdout, done.stdout + done.stderr
    text = profile.read_text()
    (x, y), *rest = tomllib.loads(text)["output"]["keystone"]
    assert 0.05 < x < 0.15 and 0.05 < y < 0.15 and rest == [[1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    assert "# keep me" in text
