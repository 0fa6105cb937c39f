"""Real OSCeleton traffic in, OSCeleton out: ISSV_DATA's recorded sessions, replayed by
`issv osc-replay` to osc-in, come out of the OSCeleton preset as OSCeleton sent them.

The sessions' licence is unknown: they stay in ISSV_DATA and this test skips without it. They were
recorded from an OSCeleton run with an unrecorded -mx/-ox (tests/backends/oscin/test_sessions.py);
osc-in undoes it, the preset sends OSCeleton's plain mapping, so each joint comes back as
(x_in - ox) / mx, y_in, z_in.
"""
import os
import threading
import time
from collections import defaultdict
from pathlib import Path

import numpy as np
import pytest

from backends.oscin.backend import OscInBackend, OscInOptions
from backends.oscin.replay import read_qlist
from tests.backends.oscin.helpers import replay
from tests.backends.oscin.test_sessions import MULTIPLIER, OFFSET
from tests.effects.osc.helpers import free_port, make_osc, run_show_with
from tests.effects.osc.test_bridges import _listening

DATA = Path(os.environ["ISSV_DATA"]) / "osceleton-sessions" if os.environ.get("ISSV_DATA") else None
pytestmark = pytest.mark.skipif(DATA is None or not DATA.is_dir(),
                                reason="needs the real OSCeleton sessions: set ISSV_DATA to the shared data folder")
SPEED = 4.0


def test_a_real_two_user_session_comes_out_as_osceleton_sent_it(receiver):
    path = DATA / "two-users.txt"
    port = free_port()
    backend = OscInBackend(None, OscInOptions(port=port, multiplier=MULTIPLIER, offset=OFFSET, lost_timeout_s=5.0,
                                              end_after_idle_s=3.0), warn=lambda text: None)
    senders = []

    def send_when_listening() -> None:
        deadline = time.monotonic() + 30
        while not _listening(port) and time.monotonic() < deadline:
            time.sleep(0.02)
        senders.append(replay(path, port, "--speed", str(SPEED), "--time-tags"))

    threading.Thread(target=send_when_listening, daemon=True).start()
    run_show_with(backend, [make_osc(destinations=[receiver.address], scheme="osceleton")])
    assert senders and senders[0].wait(60) == 0, senders[0].stderr.read()
    assert receiver.wait_for(lambda r: len(r.messages("/lost_user")) == 2)

    sent_in: dict[tuple[str, int], list] = defaultdict(list)
    for line in read_qlist(path):
        if line.address == "/joint":
            (_, name), (_, user), (_, x), (_, y), (_, z) = line.args
            sent_in[(name, user)].append(((x - OFFSET[0]) / MULTIPLIER[0], y, z))
    out = receiver.messages()
    events = [(a, args[0]) for a, _, args in out if a in ("/new_user", "/new_skel", "/lost_user")]
    for user in (1, 2):  # each user announced, calibrated and lost once, in that order
        assert [a for a, u in events if u == user] == ["/new_user", "/new_skel", "/lost_user"]
    joints: dict[tuple[str, int], list] = defaultdict(list)
    for _, types, (name, user, x, y, z) in [m for m in out if m[0] == "/joint"]:
        assert types == "sifff"
        joints[(name, user)].append((x, y, z))
    assert set(joints) == set(sent_in)  # every joint OSCeleton sent, under its own name
    for key, got in joints.items():
        expected, got = np.array(sent_in[key]), np.array(got)
        nearest = np.abs(got[:, None, :] - expected[None, :, :]).max(axis=2).min(axis=1)
        assert nearest.max() < 1e-4, key  # osc-in keeps millimetres to the hundredth
