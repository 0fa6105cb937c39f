"""`openiss-nite` driving NiTE2 through the `openni` bindings, against the FAKE bindings (fakes/)."""
from __future__ import annotations

import numpy as np
import pytest

from backends.sdk.nite import NiteBackend, hand_state
from host import GestureState, GestureType, HandState
from tests.backends.sdk.sources import Camera, Oni

R, L = (200.0, 100.0, 1500.0), (-250.0, 50.0, 1600.0)
INTRINSICS = (300.0, 310.0, 80.0, 60.0)


def depth(i: int) -> np.ndarray:
    d = np.full((120, 160), 2500, np.uint16)
    d[10 + i, :] = 1000 + i
    return d


def scene(n: int = 30):
    """R waves (frames 3-5), raises (10), touches the border (15-17), leaves (20); L clicks (24)."""
    from openni.nite2 import FakeNiteFrame, FakeScene

    frames = []
    for i in range(n):
        r = (R[0] + 5 * i, R[1], R[2])
        f = FakeNiteFrame(depth(i), hands={"R": r} if i < 20 else {}, touching_fov={"R"} if 15 <= i <= 17 else set())
        if i >= 22:
            f.hands["L"] = L
        if i in (3, 4):
            f.gestures.append(("NITE_GESTURE_WAVE", r, "NITE_GESTURE_STATE_IN_PROGRESS"))
        if i == 5:
            f.gestures.append(("NITE_GESTURE_WAVE", r, "NITE_GESTURE_STATE_COMPLETED"))
        if i == 10:
            f.gestures.append(("NITE_GESTURE_HAND_RAISE", r, "NITE_GESTURE_STATE_COMPLETED"))
        if i == 24:
            f.gestures.append(("NITE_GESTURE_CLICK", L, "NITE_GESTURE_STATE_COMPLETED"))
        frames.append(f)
    return FakeScene(frames, INTRINSICS)


@pytest.fixture
def nite(fake_sdks, tmp_path, monkeypatch):
    """A FAKE NiTE2 runtime folder and one FAKE sensor playing `scene()`."""
    from openni import nite2, openni2

    (tmp_path / "libNiTE2.so").write_bytes(nite2.FAKE_RUNTIME)
    monkeypatch.setenv("NITE2_REDIST", str(tmp_path))
    monkeypatch.delenv("NITE2_REDIST64", raising=False)
    openni2.fake_devices[b"fake://sensor"] = scene()
    return tmp_path


def run(backend, n=None):
    out = []
    while (n is None or len(out) < n) and (frame := backend.update()) is not None:
        out.append(frame)
    return out


def test_nite2_runs_and_says_so_once(nite, capsys):
    backend = NiteBackend(Camera(), NiteBackend.Options(device="any"))
    assert NiteBackend.implementation(backend.options, backend.source).sdk
    with backend:
        assert backend.runs_sdk
    NiteBackend(Camera(), NiteBackend.Options(device="any")).init()
    err = capsys.readouterr().err
    assert err.count("openiss-nite") == 1 and f"driving NiTE2 from {nite}" in err


def test_focus_gesture_starts_tracking_where_it_happened_with_stable_ids_and_states(nite):
    with NiteBackend(Camera(), NiteBackend.Options(device="any")) as backend:
        frames = run(backend, 30)
    gestures = [g for f in frames for g in f.gestures]
    wave = [g for g in gestures if g.type is GestureType.WAVE]
    assert [g.state for g in wave] == [GestureState.IN_PROGRESS, GestureState.COMPLETE]  # NiTE repeats; we don't
    done = wave[1]
    assert done.position == pytest.approx((R[0] + 25, R[1], R[2]))
    assert all(not f.hands for f in frames[:6])  # no hand before the focus gesture (NiTE semantics)
    right = [h for f in frames[6:20] for h in f.hands]
    assert {h.id for h in right} == {done.hand_id} and done.hand_id > 0
    states = [h.state for h in right]
    assert states[0] is HandState.NEW and states[1] is HandState.TRACKING
    assert states[15 - 6: 18 - 6] == [HandState.TOUCHING_FOV] * 3
    assert right[4].position == pytest.approx((R[0] + 50, R[1], R[2]))  # NiTE's mm, axes unchanged
    assert [h.state for h in frames[20].hands] == [HandState.LOST]
    raise_ = [g for g in gestures if g.type is GestureType.HAND_RAISE]
    assert len(raise_) == 1 and raise_[0].hand_id == done.hand_id  # the tracked hand near it
    click = [g for g in gestures if g.type is GestureType.CLICK]
    assert len(click) == 1 and click[0].hand_id not in (0, done.hand_id)
    assert {h.id for h in frames[25].hands} == {click[0].hand_id}
    assert all(g.name in ("wave", "click", "hand_raise") for g in gestures)


def test_depth_is_an_owned_copy_in_nite2s_own_geometry(nite):
    with NiteBackend(Camera(), NiteBackend.Options(device="any")) as backend:
        frames = run(backend, 8)
        assert backend.world_to_depth((300.0, 0.0, 1500.0)) == pytest.approx((80 + 300 * 300 / 1500, 60, 1500))
    for i, f in enumerate(frames):  # NiTE wiped each frame's memory on release
        assert np.array_equal(f.depth.data, depth(i))
    assert frames[0].depth.intrinsics.as_list() == pytest.approx(list(INTRINSICS))
    assert [round(f.timestamp, 3) for f in frames[:3]] == [0.0, 0.033, 0.067]
    assert [f.seq for f in frames] == list(range(1, 9))


def test_start_and_stop_really_start_and_stop_nite2(nite):
    from openni.nite2 import GestureType as Nite

    backend = NiteBackend(Camera(), NiteBackend.Options(device="any"))
    backend.init()
    tracker = backend._sdk.tracker
    assert tracker.fake_detecting == set()
    backend.start_gesture_detection()
    assert tracker.fake_detecting == {0, 1, 2}
    backend.start_hand_tracking()
    run(backend, 8)  # the wave at frame 5 starts tracking a hand
    assert tracker.fake_tracked
    backend.stop_gesture_detection()  # focus gestures stay on: hands still need them
    assert tracker.fake_detecting == {int(Nite.NITE_GESTURE_WAVE), int(Nite.NITE_GESTURE_CLICK)}
    assert all(not f.gestures for f in run(backend, 20))
    backend.stop_hand_tracking()
    assert tracker.fake_detecting == set() and not tracker.fake_tracked
    device = backend._sdk.device
    backend.stop()
    assert tracker.fake_closed and device.fake_closed and not backend.runs_sdk


def test_an_oni_recording_ends_instead_of_blocking(nite):
    source = Oni(b"fake://sensor", frames=12)
    with NiteBackend(source) as backend:
        frames = run(backend)
    assert len(frames) == 12 and all(not f.depth.mirrored for f in frames)


def test_an_unplugged_sensor_mid_show_is_said_once_and_the_engine_takes_the_same_source(nite, capsys):
    from openni import openni2

    openni2.fake_devices[b"fake://sensor"].unplugged_at = 6
    source = Oni(b"fake://sensor", frames=30)
    with NiteBackend(source) as backend:
        frames = run(backend)
        assert not backend.runs_sdk
    assert len(frames) == 6 + len(source.scene) and [f.seq for f in frames] == list(range(1, len(frames) + 1))
    assert source.opened == 2 and source.closed == 2  # closed after NiTE, opened afresh for the engine
    err = capsys.readouterr().err
    assert err.count("NiTE2 stopped delivering frames") == 1 and "switching to the open engine in NiTE mode" in err


@pytest.mark.parametrize("bits, state", [(0, HandState.LOST), (1 | 2, HandState.NEW), (2, HandState.TRACKING),
                                         (2 | 4, HandState.TOUCHING_FOV), (1 | 2 | 4, HandState.NEW)])
def test_hand_states_are_read_as_nite2s_bit_flags(bits, state):
    assert hand_state(bits) is state
