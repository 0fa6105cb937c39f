"""The user-aware effects on a real OSCeleton session (ISSV_DATA/osceleton-sessions/one-user.txt)
replayed by `issv osc-replay` to osc-in over UDP: one user, both hands reported all the time (the
arms coming up and down), as a tracker of whole people reports them. The session's licence is
unknown, so it stays in ISSV_DATA and these tests skip without it."""
import os
from pathlib import Path

import numpy as np
import pytest

from effects.console import ConsoleEffect
from effects.digieviss import DigiEVISS
from host import Gesture, GestureState, GestureType, HandState, Side, Stage
from tests.backends.oscin.helpers import backend, collect, replay
from tests.backends.oscin.test_sessions import MULTIPLIER, OFFSET

DATA = Path(os.environ["ISSV_DATA"]) / "osceleton-sessions" if os.environ.get("ISSV_DATA") else None
pytestmark = pytest.mark.skipif(DATA is None or not DATA.is_dir(),
                                reason="needs the real OSCeleton sessions: set ISSV_DATA to the shared data folder")
USER = 3  # the session's only user


@pytest.fixture(scope="module")
def frames():
    with backend(multiplier=MULTIPLIER, offset=OFFSET, lost_timeout_s=5.0, end_after_idle_s=3.0) as b:
        sender = replay(DATA / "one-user.txt", b.port, "--speed", "4", "--time-tags")
        got = collect(b)
    assert sender.wait(120) == 0, sender.stderr.read()
    return got


def right_hand(frame):
    return next((h for h in frame.hands if h.user_id == USER and h.side is Side.RIGHT), None)


def test_the_console_speaks_of_the_user_not_of_arms_coming_down(frames, capsys):
    ups = [right_hand(f).extended for f in frames if right_hand(f) is not None]
    assert ups.count(True) > 30 and ups.count(False) > 30  # the right arm really comes up and down
    assert sum(a != b for a, b in zip(ups, ups[1:])) >= 2
    effect = ConsoleEffect(ConsoleEffect.Options())
    effect.setup(Stage((64, 48), 30.0, "osc-in"))
    for frame in frames:
        effect.on_frame(frame)
    events = [line.split("s  ", 1)[1].split(" at ")[0].strip() for line in capsys.readouterr().out.splitlines()]
    assert events == [f"user {USER} new", f"hand {10 * USER + 1} new  left    of user {USER}",
                      f"hand {10 * USER + 2} new  right   of user {USER}",
                      f"user {USER} lost", f"hand {10 * USER + 1} lost", f"hand {10 * USER + 2} lost"]


def test_digieviss_carries_a_sphere_in_a_real_hand_through_its_rests(frames, tmp_path):
    """A sphere is put where the right hand first sticks out and grabbed there: it stays in that
    hand, resting at the performer's side or raised, until the user leaves."""
    start = next(i for i, f in enumerate(frames) if (h := right_hand(f)) is not None and h.extended)
    hand = right_hand(frames[start])
    far = tuple(np.add(hand.position, (3000.0, 3000.0, 0.0)))
    spheres = [{"evidence": "A", "value": "a", "position": hand.position}, {"evidence": "B", "value": "b", "position": far}]
    effect = DigiEVISS(DigiEVISS.Options(spheres=spheres, program=str(tmp_path / "out.ipl"), hold_timeout_s=0, log=False))
    effect.setup(Stage((64, 48), 30.0, "osc-in"))
    effect.on_gesture(Gesture(GestureType.CLICK, GestureState.COMPLETE, hand.position, hand.id, Side.RIGHT,
                              timestamp=frames[start].timestamp, user_id=USER))
    resting = 0
    for frame in frames[start:]:
        effect.on_frame(frame)
        h = right_hand(frame)
        if h is None or not h.in_view:
            break
        assert str(effect.scene.holder(effect.scene.spheres[0])) == "user 3 right hand"
        assert effect.scene.spheres[0].center == pytest.approx(h.position)
        resting += not h.extended
    assert resting > 30 and h is not None and h.state is HandState.LOST
    effect.close()
