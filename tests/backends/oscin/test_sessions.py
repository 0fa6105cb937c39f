"""The real OSCeleton sessions (ISSV_DATA/osceleton-sessions) replayed by `issv osc-replay` to osc-in.

Their licence is unknown, so they stay in ISSV_DATA and these tests skip without it. The sessions'
x reaches 3.26: the OSCeleton that recorded them ran with an unrecorded -mx/-ox. MULTIPLIER and
OFFSET undo it as far as the data tell: the one joint sent at X = 0 (`r_hip 2 1.74722 0.5 0`:
ox + mx / 2 = 1.747, with y and z untouched) and the bone lengths, most constant at mx = 5.
"""
import os
from collections import defaultdict
from pathlib import Path

import numpy as np
import pytest

from backends.oscin.backend import OscInOptions
from backends.oscin.replay import instants, read_qlist, session_seconds
from backends.oscin.schemes import OSCeletonScheme, UserEvent
from backends.users import Users
from host import HandState, Joint
from tests.backends.oscin.helpers import backend, collect, replay

DATA = Path(os.environ["ISSV_DATA"]) / "osceleton-sessions" if os.environ.get("ISSV_DATA") else None
pytestmark = pytest.mark.skipif(DATA is None or not DATA.is_dir(),
                                reason="needs the real OSCeleton sessions: set ISSV_DATA to the shared data folder")
MULTIPLIER, OFFSET = (5.0, 1.0, 1.0), (-0.753, 0.0, 0.0)
SPEED = 4.0


def _wire(tag: str, value):
    """A value as OSC carries it: `f` is a 32-bit float (as OSCeleton and Pd send them)."""
    return float(np.float32(value)) if tag == "f" else value


def _in_process(path: Path) -> list:
    """The gestures osc-in's parts find on the session without a network: the reference."""
    options = OscInOptions(multiplier=MULTIPLIER, offset=OFFSET)
    scheme = OSCeletonScheme(MULTIPLIER, OFFSET)
    from backends.oscin.backend import OscInBackend
    users = Users(lambda: OscInBackend.recognizer(options), 1e9, True, options.reach_mm)
    gestures = []
    groups = instants(read_qlist(path))
    for group in groups:
        t = session_seconds(group[0])  # what osc-in's clock reads from the time tags
        samples: dict[int, dict] = defaultdict(dict)
        for line in group:
            for event in scheme.read(line.address, [_wire(tag, v) for tag, v in line.args]):
                if isinstance(event, UserEvent):
                    if event.kind == "new":
                        users.announce(event.user, 0.0)
                    else:
                        gestures += users.leave(event.user, t)
                else:
                    samples[event.user][event.joint] = Joint(event.position, event.confidence)
        for user, joints in samples.items():
            gestures += users.sample(user, joints, t, 0.0)
        users.report()
    return gestures


def _run(name: str):
    path = DATA / name
    # generous timeouts: a loaded machine may stall the sender for a second
    with backend(multiplier=MULTIPLIER, offset=OFFSET, lost_timeout_s=5.0, end_after_idle_s=3.0) as b:
        sender = replay(path, b.port, "--speed", str(SPEED), "--time-tags")
        frames = collect(b)
    assert sender.wait(120) == 0, sender.stderr.read()
    assert b.receiver.bad.total() == 0
    return path, frames


def _lifecycle(frames) -> dict[int, list[tuple[str, float]]]:
    out: dict[int, list] = defaultdict(list)
    for f in frames:
        for u in f.users:
            if not out[u.id] or out[u.id][-1][0] != u.state.value:
                out[u.id].append((u.state.value, f.time))
    return dict(out)


@pytest.mark.parametrize("name, users", [("one-user.txt", {3}), ("two-users.txt", {1, 2})])
def test_real_session_users_bodies_in_mm_and_gestures(name, users):
    path, frames = _run(name)
    life = _lifecycle(frames)
    assert set(life) == users
    for user, states in life.items():
        assert [s for s, _ in states] == ["new", "tracking", "lost"]  # each /lost_user once, at its time
    if name == "one-user.txt":
        # the session's own clock: /new_user at 1.0 s, /lost_user at 50.4 s
        assert life[3][0][1] == pytest.approx(1.0) and life[3][2][1] == pytest.approx(50.4, abs=0.05)
    else:
        assert life[1][2][1] < life[2][2][1]  # user 1 leaves first
    bodies = [u for f in frames for u in f.users if u.state is HandState.TRACKING and len(u.joints) >= 13]
    assert len(bodies) > 500
    for u in bodies:
        j = {name: joint.position for name, joint in u.joints.items()}
        assert j["head"][1] > j["torso"][1] > j["left_knee"][1]  # y up, in mm
        assert 150 < j["head"][1] - j["torso"][1] < 800
        assert all(1000 < p[2] < 3600 for p in j.values() if p[2] > 0)  # 1-3.6 m from the sensor
        assert abs(j["torso"][0]) < 1200  # x, with the session's -mx/-ox undone
    got = [g for f in frames for g in f.gestures]
    reference = _in_process(path)
    assert got and got == reference  # over UDP at 4x with time tags: the very same gestures (times,
    # positions, confidences to the last bit) as without a network
