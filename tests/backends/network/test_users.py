"""Users between real processes: osc-in in `issv serve` (fed by `issv osc-replay`) -> the network backend."""
from __future__ import annotations

import pytest

from backends.network.backend import NetworkBackend, NetworkOptions
from host import HandState, frames_of
from tests.backends.network.conftest import free_ports
from tests.backends.oscin.helpers import body_at, hands_at, replay, write_session
from tests.effects.osc.helpers import free_port


def duet(tmp_path) -> tuple:
    """A duet as OSCeleton would send it (user 2 joins at frame 10) and an `issv serve` profile
    whose osc-in listens for it: (session file, profile, osc-in's port)."""
    frames = [hands_at(1, i) + (hands_at(2, i, 900.0) if i >= 10 else []) for i in range(45)]
    bodies = [{**body_at(1), **(body_at(2, 900.0) if i >= 10 else {})} for i in range(45)]
    session = write_session(tmp_path / "duet.txt", frames, bodies=bodies)
    osc_port = free_port()
    profile = tmp_path / "serve.toml"
    # the users time out (LOST) a second before the stream ends, so the LOST frames are always in it
    profile.write_text(f'[backend]\nname = "osc-in"\nport = {osc_port}\nlost_timeout_s = 0.5\nend_after_idle_s = 1.5\n')
    return session, profile, osc_port


def test_users_and_resting_hands_arrive_over_the_wire(serve, tmp_path):
    session, profile, osc_port = duet(tmp_path)
    port = free_ports()
    serve(str(profile), "--bind", f"tcp://127.0.0.1:{port}")
    with NetworkBackend(None, NetworkOptions(connect=f"tcp://127.0.0.1:{port}", end_with_publisher=True,
                                             depth=False)) as backend:
        sender = replay(session, osc_port)
        got = list(frames_of(backend))
    assert sender.wait(60) == 0, sender.stderr.read()
    with_users = [f for f in got if f.users]
    assert len(with_users) >= 30 and got[0].backend == "osc-in"
    ids = [{u.id for u in f.users} for f in with_users]
    assert {1} in ids and {1, 2} in ids
    two = next(f for f in with_users if len(f.users) == 2)
    user2 = next(u for u in two.users if u.id == 2)
    assert user2.joints["torso"].position == pytest.approx((900.0, 0.0, 2100.0), abs=0.01)
    assert set(user2.joints) >= {"torso", "head", "left_hand", "right_hand"}
    # both hands of every user, every frame, each saying whether it is extended, with its user
    for f in with_users:
        in_view = [u.id for u in f.users if u.in_view]
        assert sorted(h.user_id for h in f.hands if h.in_view) == sorted(2 * in_view)
        assert all(h.extended is not None for h in f.hands)
    assert any(u.state is HandState.LOST for f in got for u in f.users)
