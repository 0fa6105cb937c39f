"""console: users come and go, their hands with them; an arm coming down is no event."""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

from effects.console import ConsoleEffect
from host import DepthFrame, Frame, Hand, HandState, Intrinsics, Side, Stage, User

K = Intrinsics(100, 100, 8, 6)
REST, UP = (250.0, -350.0, 2000.0), (300.0, 400.0, 1700.0)


def frame(i, users=(), hands=()):
    depth = DepthFrame(np.zeros((12, 16), np.uint16), K, i, i / 30)
    return Frame(i, depth.capture_time, depth, tuple(hands), (), "script", users=tuple(users))


def user_frames():
    """User 1 stands with both hands reported all the time, raises the right arm twice (the
    hand resting between, under the same id), then leaves; user 2 comes in meanwhile."""
    out = []
    for i in range(1, 41):
        state = HandState.NEW if i == 1 else HandState.LOST if i == 40 else HandState.TRACKING
        up = 5 <= i < 12 or 20 <= i < 28
        one = User(1, state, center_of_mass=(200.0, 0.0, 2000.0))
        hands = [Hand(11, state, (-250.0, -350.0, 2000.0), Side.LEFT, 1, extended=False),
                 Hand(12, state, UP if up else REST, Side.RIGHT, 1, extended=up)]
        users = [one]
        if i >= 30:
            users.append(User(2, HandState.NEW if i == 30 else HandState.TRACKING, center_of_mass=(-900.0, 0.0, 2500.0)))
        out.append(frame(i, users, hands))
    return out


def run(frames, capsys, **options):
    effect = ConsoleEffect(ConsoleEffect.Options(**options))
    effect.setup(Stage((64, 48), 30.0, "script"))
    for f in frames:
        effect.on_frame(f)
    return capsys.readouterr().out.splitlines()


def test_users_come_and_go_and_a_resting_arm_is_no_event(capsys):
    lines = [line.split("s  ", 1)[1] for line in run(user_frames(), capsys)]
    assert lines == [
        "user 1 new  at (200, 0, 2000) mm",
        "hand 11 new  left    of user 1 at (-250, -350, 2000) mm",
        "hand 12 new  right   of user 1 at (250, -350, 2000) mm",
        "user 2 new  at (-900, 0, 2500) mm",
        "user 1 lost",
        "hand 11 lost",
        "hand 12 lost",
    ]


def test_json_lines_name_the_user(capsys):
    docs = [json.loads(line) for line in run(user_frames(), capsys, format="json")]
    assert [(d["type"], d.get("user"), d.get("hand")) for d in docs] == [
        ("user_new", 1, None), ("hand_new", 1, 11), ("hand_new", 1, 12), ("user_new", 2, None),
        ("user_lost", 1, None), ("hand_lost", None, 11), ("hand_lost", None, 12)]
    assert docs[0]["position"] == [200.0, 0.0, 2000.0] and docs[2]["side"] == "right"


def test_a_backend_of_hands_only_shows_each_hands_coming_and_going(capsys):
    frames = [frame(i, hands=[Hand(1, HandState.TRACKING, UP, Side.RIGHT)] if 3 <= i < 6 else []) for i in range(1, 9)]
    lines = [line.split("s  ", 1)[1] for line in run(frames, capsys)]
    assert lines == ["hand 1 new  right   at (300, 400, 1700) mm", "hand 1 lost"]


def test_the_demo_show_no_longer_loses_a_hand_when_the_arm_comes_down(tmp_path):
    """profiles/demo.toml (synthetic performer -> openiss -> console) for 12 s: the arm comes down
    after the wave at 2.7 s and the swipes, where the demo used to say "hand 1 lost" each time."""
    profile = Path(__file__).resolve().parents[2] / "profiles" / "demo.toml"
    run = subprocess.run([sys.executable, "-m", "host", "run", str(profile), "--headless", "--fast", "--seconds", "12"],
                         cwd=tmp_path, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    events = [line.split("s  ", 1)[1] for line in run.stdout.splitlines() if "s  " in line]
    assert sum(e.startswith("gesture ") for e in events) >= 3  # wave, swipe_left, swipe_right, click
    hands = [e for e in events if e.startswith("hand ")]
    assert not [e for e in events if " lost" in e], run.stdout
    assert sorted(e.split()[3] for e in hands) == ["left", "right"]  # each hand new once, both all along
