"""`issv calibrate`: point pairs -> homography saved into the profile (comments kept), keystone
corners checked, and the interactive session's logic (hold a hand on a target, drag corners)."""
import shutil
import subprocess
import sys
import textwrap
import tomllib
from pathlib import Path

import numpy as np
import pytest

from host.cli import main
from host.model import DepthFrame, Frame, Hand, HandState, Intrinsics, Side
from host.render.calibration import apply, homography, project
from host.render.interactive import HOLD_S, TARGETS, Session
from tests.conftest import write_clip

ROOT = Path(__file__).resolve().parents[3]
TRUE_H = np.array([[3.1, 0.2, 40.0], [-0.1, 2.9, 25.0], [0.0004, 0.0002, 1.0]])

PROFILE = """# my show: keep this comment
backend = "truth"   # the null tracker

[source]
name = "clip"
path = "{clip}"

[output]
mode = "headless"   # no window here
size = [1280, 720]
"""


@pytest.fixture
def profile(tmp_path):
    path = tmp_path / "show.toml"
    path.write_text(PROFILE.format(clip=write_clip(tmp_path / "clip.npz")))
    return path


def test_homography_recovers_a_known_mapping_from_noisy_points():
    rng = np.random.default_rng(3)
    cam = rng.uniform([0, 0], [320, 240], (12, 2))
    stage = apply(TRUE_H, cam) + rng.normal(0, 0.3, (12, 2))
    h = homography(cam, stage)
    grid = np.array([(x, y) for x in (0, 160, 320) for y in (0, 120, 240)], float)
    assert np.abs(apply(h, grid) - apply(TRUE_H, grid)).max() < 2.0


def test_homography_refuses_collinear_points():
    with pytest.raises(ValueError, match="degenerate"):
        homography([(0, 0), (1, 1), (2, 2), (3, 3)], [(0, 0), (1, 0), (0, 1), (1, 1)])


def test_calibrate_from_depth_pixels_saves_the_matrix_and_keeps_the_comments(profile, tmp_path):
    cam = [(20, 30), (300, 25), (290, 220), (30, 210), (160, 120)]
    points = tmp_path / "points.csv"
    points.write_text("u,v,stage_x,stage_y\n" + "".join(f"{u},{v},{x},{y}\n" for (u, v), (x, y) in zip(cam, apply(TRUE_H, cam))))
    assert main(["calibrate", str(profile), "--points", str(points)]) == 0
    text = profile.read_text()
    assert "# my show: keep this comment" in text and "# no window here" in text and "# the null tracker" in text
    saved = np.array(tomllib.loads(text)["output"]["calibration"])
    assert np.allclose(saved, TRUE_H / TRUE_H[2, 2], rtol=1e-5, atol=1e-7)


def test_calibrate_from_camera_mm_uses_the_sources_intrinsics(profile, tmp_path):
    k = Intrinsics(320 * 0.89, 320 * 0.89, 160, 120)  # what tests.conftest.write_clip writes
    world = [(-600, 400, 2000), (600, 420, 2100), (650, -400, 2500), (-640, -380, 2400), (0, 0, 3000)]
    stage = [apply(TRUE_H, [k.world_to_depth(*p)[:2]])[0] for p in world]
    points = tmp_path / "points.csv"
    points.write_text("x,y,z,stage_x,stage_y\n" + "".join(f"{x},{y},{z},{sx},{sy}\n" for (x, y, z), (sx, sy) in zip(world, stage)))
    assert main(["calibrate", str(profile), "--points", str(points)]) == 0
    saved = tomllib.loads(profile.read_text())["output"]["calibration"]
    depth = DepthFrame(np.zeros((240, 320), np.uint16), k)
    for p, want in zip(world, stage):
        assert np.allclose(project(p, depth, (1280, 720), saved), want, atol=0.01)


def test_too_few_points_or_a_bad_header_is_one_clear_line(profile, tmp_path, capsys):
    points = tmp_path / "points.csv"
    points.write_text("u,v,stage_x,stage_y\n1,2,3,4\n5,6,7,8\n")
    assert main(["calibrate", str(profile), "--points", str(points)]) == 1
    assert "at least 4 point pairs, got 2" in capsys.readouterr().err
    points.write_text("a,b\n1,2\n")
    assert main(["calibrate", str(profile), "--points", str(points)]) == 1
    assert "expected a header" in capsys.readouterr().err
    points.write_bytes(b"\xff\xfe\x00photo" * 20)  # a picture given for the points file
    assert main(["calibrate", str(profile), "--points", str(points)]) == 1
    assert f"{points}: cannot read the points file" in capsys.readouterr().err
    assert "calibration" not in profile.read_text()


def test_keystone_corners_are_checked_and_saved(profile, capsys):
    assert main(["calibrate", str(profile), "--keystone", "0.05,0", "1,0.1", "0.9,1", "0,0.9"]) == 0
    assert tomllib.loads(profile.read_text())["output"]["keystone"] == [[0.05, 0], [1, 0.1], [0.9, 1], [0, 0.9]]
    assert main(["calibrate", str(profile), "--keystone", "0,0", "1,1", "1,0", "0,1"]) == 1
    assert "convex" in capsys.readouterr().err
    assert main(["calibrate", str(profile), "--reset"]) == 0
    assert "keystone" not in tomllib.loads(profile.read_text())["output"]


def frame_with_hand(position):
    k = Intrinsics(285.6, 285.6, 160, 120)
    depth = DepthFrame(np.zeros((240, 320), np.uint16), k)
    return Frame(1, 0.0, depth, (Hand(1, HandState.TRACKING, position, Side.RIGHT),))


def test_a_hand_held_on_each_target_makes_the_calibration():
    session = Session((1280, 720), None)
    truth = np.array([[4.0, 0.0, 0.0], [0.0, 3.0, 0.0], [0.0, 0.0, 1.0]])  # depth px -> stage px
    k = frame_with_hand((0, 0, 1)).depth.intrinsics
    t = 0.0
    for fx, fy in TARGETS:
        u, v = fx * 1280 / 4, fy * 720 / 3  # where a hand on this target shows in the depth image
        z = 2000.0
        position = k.depth_to_world(u, v, z)
        for step in range(int(HOLD_S / 0.1) + 2):
            jitter = (5.0 * (step % 2), 0.0, 0.0)  # a real hand is never quite still
            session.hand(frame_with_hand(tuple(np.add(position, jitter))), t)
            t += 0.1
        session.hand(None, t)  # the hand goes away before the next target
    assert session.target is None and len(session.pairs) == len(TARGETS)
    result = session.result()
    grid = np.array([(u, v) for u in (0, 160, 320) for v in (0, 120, 240)], float)
    # within the 5 mm jitter (0.7 depth pixels, 3 stage pixels at this scale)
    assert np.abs(apply(result["calibration"], grid) - apply(truth, grid)).max() < 4.0
    assert result["keystone"] == [[0, 0], [1, 0], [1, 1], [0, 1]]


def test_a_moving_hand_is_not_taken():
    session = Session((1280, 720), None)
    for i in range(40):
        session.hand(frame_with_hand((-400.0 + 20 * i, 0.0, 2000.0)), i * 0.1)
    assert session.pairs == []


def test_dragging_a_corner_moves_it_but_never_folds_the_quad():
    session = Session((1000, 500), None)
    session.press(995, 8)  # near the top-right corner
    session.drag(900, 50)
    assert session.corners[1] == [0.9, 0.1]
    session.drag(0, 500)  # onto the bottom-left: not convex any more, ignored
    assert session.corners[1] == [0.9, 0.1]
    session.press(500, 250)  # nowhere near a corner
    session.drag(10, 10)
    assert session.corners[0] == [0.0, 0.0]


WINDOWED = textwrap.dedent("""
    import sys
    from backends.truth import TruthBackend
    from host import profile as profiles
    from host.render import interactive
    from host.render.context import Window

    class Failing(TruthBackend):
        '''Raises on frame 5, or (with "always") on every frame from the 5th.'''
        calls = 0
        def update(self):
            frame, Failing.calls = super().update(), Failing.calls + 1
            if Failing.calls == 5 or (sys.argv[2] == "always" and Failing.calls > 5):
                raise ZeroDivisionError("odd frame")
            return frame

    seen, presents = [], [0]
    hand = interactive.Session.hand
    interactive.Session.hand = lambda self, frame, now: (seen.append(frame and frame.seq), hand(self, frame, now))
    present = Window.present
    def counted(self):
        present(self)
        presents[0] += 1
        if presents[0] == 45:  # about 1.5 s at 30 Hz: the user closes the window (Escape: cancel)
            self.wnd.close()
    Window.present = counted
    original = interactive.make_backend
    interactive.make_backend = lambda prof: Failing(original(prof).source)
    result = interactive.calibrate_interactively(profiles.load(sys.argv[1]))
    print("frames", len({s for s in seen if s}), "result", result)
""")


@pytest.mark.skipif(shutil.which("xvfb-run") is None, reason="needs xvfb-run (apt-get install xvfb) for a real window")
@pytest.mark.parametrize("failing", ["once", "always"])
def test_the_calibration_window_drives_the_backend_through_the_frame_loop(profile, failing):
    """A frame the backend raises on is skipped and the window goes on (the show's rules); a backend
    failing frame after frame is reported when the window closes, not lost with a dead thread."""
    text = profile.read_text().replace('mode = "headless"   # no window here', 'mode = "window"\nfps = 30')
    text = text.replace("size = [1280, 720]", "size = [320, 240]")
    profile.write_text(text.replace('path = "', 'loop = true\npath = "'))
    run = subprocess.run(["xvfb-run", "-a", sys.executable, "-c", WINDOWED, str(profile), failing],
                         capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert "raised ZeroDivisionError on frame 5" in run.stderr and "the frame is skipped" in run.stderr, run.stderr
    if failing == "once":
        assert run.returncode == 0, run.stderr
        frames = int(run.stdout.split()[1])
        assert frames >= 20 and "result None" in run.stdout  # frames kept coming after the bad one
    else:
        assert run.returncode == 1 and "Traceback" in run.stderr  # calibrate_interactively raised ...
        assert "UserError: issv: backend 'truth' failed: ZeroDivisionError: odd frame" in run.stderr  # ... one line
