"""`openiss-nuitrack` driving PyNuitrack, against the FAKE bindings (fakes/PyNuitrack)."""
from __future__ import annotations

import numpy as np
import pytest

from backends.sdk.nuitrack import NuitrackBackend
from host import GestureState, HandState, Side
from tests.backends.engine import choreography as c
from tests.backends.sdk.sources import Camera, Recording

SHOULDER = np.array([180.0, 250.0, 0.0])  # the performer's right shoulder from the torso (mirrored view)


def depth(i: int) -> np.ndarray:
    d = np.full((60, 80), 2600, np.uint16)
    d[i % 60, :] = 900
    return d


def nuitrack_frames(performance: c.Performance, t0: float = 0.0, drop=None):
    """A choreography as Nuitrack's skeleton of user 1 (hands, torso, head, shoulders)."""
    from PyNuitrack.py_nuitrack import FakeNuitrackFrame

    sign = 1.0 if performance.mirrored else -1.0
    out = []
    for i, (t, hands, body) in enumerate(performance.frames()):
        torso = np.array(body["torso"])
        joints = {"torso": (body["torso"], 0.9), "head": (body["head"], 0.9),
                  "right_shoulder": (tuple(torso + SHOULDER * [sign, 1, 1]), 0.9),
                  "left_shoulder": (tuple(torso - SHOULDER * [sign, -1, -1]), 0.9)}
        for h in hands:
            lost = drop is not None and h.side in drop[0] and drop[1] <= t < drop[2]
            joints[f"{h.side.value}_hand"] = (h.position, 0.0 if lost else 0.8)
        out.append(FakeNuitrackFrame(t0 + t, depth(i), {1: joints}))
    return out


@pytest.fixture
def sensor(fake_sdks):
    """One FAKE licensed sensor; tests give it frames."""
    from PyNuitrack import py_nuitrack

    s = py_nuitrack.FakeSensor("FAKE Astra", "AS-0001", [])
    py_nuitrack.fake_sensors[:] = [s]
    py_nuitrack.fake_instances.clear()
    return s


def run(backend, n=None):
    out = []
    while (n is None or len(out) < n) and (frame := backend.update()) is not None:
        out.append(frame)
    return out


@pytest.mark.parametrize("mirrored", [True, False])
def test_skeleton_hands_give_our_gestures_with_stable_ids_sides_and_positions(sensor, mirrored, capsys):
    performance = c.swipe()
    performance.mirrored = mirrored
    sensor.frames = nuitrack_frames(performance)
    with NuitrackBackend(Camera()) as backend:
        assert backend.runs_sdk
        frames = run(backend, len(sensor.frames))
    assert "driving Nuitrack FAKE-0.38 on FAKE Astra (serial AS-0001)" in capsys.readouterr().err
    assert all({(h.id, h.side) for h in f.hands} == {(1, Side.LEFT), (2, Side.RIGHT)} for f in frames)
    assert [h.state for h in frames[0].hands] == [HandState.NEW, HandState.NEW]
    assert all(h.state is HandState.TRACKING for f in frames[1:] for h in f.hands)
    right = [h for h in frames[10].hands if h.side is Side.RIGHT][0]
    assert right.position == pytest.approx(sensor.frames[10].users[1]["right_hand"][0])  # Nuitrack's mm, unchanged
    done = [g for f in frames for g in f.gestures if g.state is GestureState.COMPLETE]
    alone = NuitrackBackend.recognizer()  # the same recogniser on the same joints, without Nuitrack
    expected = [g for t, hands, body in performance.frames() for g in alone.update(t, hands, body, mirrored)]
    assert [(g.name, g.type.value) for g in done] == [("swipe_left", "SWIPE_LEFT")]  # the performer's left
    assert [g.name for g in done] == [g.name for g in expected if g.state is GestureState.COMPLETE]
    assert done[0].hand_id == 2 and done[0].side is Side.RIGHT and all(np.isfinite(done[0].position))
    assert frames[0].depth.mirrored is mirrored


def test_a_hand_lost_then_found_again_keeps_its_id(sensor):
    sensor.frames = nuitrack_frames(c.swipe(), drop=({Side.RIGHT}, 1.0, 2.0))
    with NuitrackBackend(Camera()) as backend:
        frames = run(backend, len(sensor.frames))
    right = [[h.state for h in f.hands if h.id == 2] for f in frames]
    flat = [s[0] if s else None for s in right]
    lost_at = flat.index(HandState.LOST)
    timeout = NuitrackBackend.Options().lost_timeout_s
    last = frames[29].timestamp  # the last frame before the joint's confidence dropped (t = 1 s)
    assert frames[lost_at - 1].timestamp - last <= timeout < frames[lost_at].timestamp - last
    assert flat[30:lost_at] == [None] * (lost_at - 30)  # unseen hands are left out, not frozen
    back = next(i for i in range(lost_at + 1, len(flat)) if flat[i] is not None)
    assert flat[back] is HandState.NEW and flat[back + 1] is HandState.TRACKING
    assert all(h.id == 1 for f in frames for h in f.hands if h.side is Side.LEFT)


def test_depth_is_an_owned_copy(sensor):
    sensor.frames = nuitrack_frames(c.swipe())[:10]
    with NuitrackBackend(Camera()) as backend:
        frames = run(backend, 10)
    for i, f in enumerate(frames):  # the bindings overwrote their buffer at every update
        assert np.array_equal(f.depth.data, depth(i))
    assert (frames[0].depth.width, frames[0].depth.height) == (80, 60)


def test_licence_expiry_mid_show_is_said_once_and_the_engine_carries_on(sensor, capsys):
    from PyNuitrack import py_nuitrack

    sensor.licensed = False
    sensor.frames = nuitrack_frames(c.swipe())[:5] + nuitrack_frames(c.swipe(), t0=179.95)[:5]
    camera = Camera()
    backend = NuitrackBackend(camera)
    backend.init()
    backend.start_hand_tracking()
    backend.start_gesture_detection()
    frames = run(backend)
    backend.stop()
    err = capsys.readouterr().err
    assert err.count("LicenseNotAcquired") == 1 and "unlicensed Nuitrack runs 3 minutes" in err
    assert py_nuitrack.fake_instances[0].fake_released
    sdk = [f for f in frames if f.depth.width == 80]
    assert len(sdk) == 5 + 2  # until 3 minutes after the first frame
    assert len(frames) == len(sdk) + len(camera.scene) and camera.opened == 1  # then the engine on the camera
    assert [f.seq for f in frames] == list(range(1, len(frames) + 1))


def test_licence_expiry_without_a_source_ends_the_show_cleanly(sensor, capsys):
    sensor.licensed = False
    sensor.frames = nuitrack_frames(c.swipe())[:3] + nuitrack_frames(c.swipe(), t0=179.95)[:5]
    with NuitrackBackend(None) as backend:
        assert len(run(backend)) == 3 + 2
    err = capsys.readouterr().err
    assert "LicenseNotAcquired" in err and "no source to fall back to: the show ends" in err


def test_a_swipe_still_pending_when_nuitrack_stops_and_the_show_ends_completes(sensor, capsys):
    """The show's end asks the backend for what its recogniser was still confirming: Nuitrack's
    session, even once it has stopped, not an open engine that never ran."""
    frames = nuitrack_frames(c.swipe())
    ends = next(n for n in range(len(frames)) if frames[n].t >= 1.9)  # the stroke is over, not yet confirmed
    sensor.frames = frames[:ends]
    waiting = NuitrackBackend.Options(gestures={"swipe_confirm_s": 0.3})  # still confirming at the cut
    with NuitrackBackend(None, waiting) as backend:
        played = run(backend)
        assert not any(g.state is GestureState.COMPLETE for f in played for g in f.gestures)
        done = backend.finish()
        assert [(g.name, g.state, g.hand_id) for g in done] == [("swipe_left", GestureState.COMPLETE, 2)]
        backend.stop_gesture_detection()
        assert backend.finish() == ()
    assert "Nuitrack delivered no depth" in capsys.readouterr().err


def test_a_sensor_that_stops_delivering_falls_back_to_the_engine(sensor, capsys):
    sensor.frames = nuitrack_frames(c.swipe())[:3]
    with NuitrackBackend(Camera()) as backend:
        frames = run(backend)
        assert not backend.runs_sdk
    assert len(frames) == 3 + len(Camera().scene)
    assert "Nuitrack delivered no depth" in capsys.readouterr().err


def test_stop_releases_nuitrack_and_leaves_the_unopened_camera_alone(sensor):
    from PyNuitrack import py_nuitrack

    sensor.frames = nuitrack_frames(c.swipe())[:3]
    camera = Camera()
    with NuitrackBackend(camera) as backend:
        run(backend, 2)
        backend.stop_hand_tracking()
        assert backend.update().hands == ()
    assert py_nuitrack.fake_instances[0].fake_released and camera.opened == 0


@pytest.mark.parametrize("sensors, source, says", [
    ([], Camera(), "Nuitrack found no depth sensor"),
    (None, Recording(), "source 'clip' is a recording"),
])
def test_no_sensor_or_a_recorded_source_runs_the_engine(sensor, sensors, source, says, capsys):
    from PyNuitrack import py_nuitrack

    if sensors is not None:
        py_nuitrack.fake_sensors[:] = sensors
    with NuitrackBackend(source) as backend:
        assert not backend.runs_sdk
        assert len(run(backend)) == len(source.scene)
    err = capsys.readouterr().err
    assert err.count("openiss-nuitrack") == 1 and says in err and "open engine in Nuitrack mode" in err
    assert all(i.fake_released for i in py_nuitrack.fake_instances)


def test_a_serial_number_that_is_not_connected_is_named(sensor, capsys):
    with NuitrackBackend(Camera(), NuitrackBackend.Options(device="XX-9")) as backend:
        assert not backend.runs_sdk
    assert "no sensor with serial 'XX-9' (connected: FAKE Astra AS-0001)" in capsys.readouterr().err


def test_a_hand_at_the_edge_of_the_image_is_touching_fov(sensor):
    from PyNuitrack.py_nuitrack import FakeNuitrackFrame

    def frame(i, right_x):
        return FakeNuitrackFrame(i / 30, depth(i), {3: {"right_hand": ((right_x, 0.0, 2400.0), 0.9),
                                                        "left_hand": ((-200.0, 0.0, 2400.0), 0.9)}})

    half_width = 2400.0 * np.tan(np.radians(NuitrackBackend.Options().fov_deg[0] / 2))  # at 2.4 m
    sensor.frames = [frame(0, 200.0), frame(1, 200.0), frame(2, half_width - 10), frame(3, 200.0)]
    with NuitrackBackend(Camera()) as backend:
        frames = run(backend, 4)
    right = [[h for h in f.hands if h.side is Side.RIGHT][0] for f in frames]
    assert [h.id for h in right] == [6] * 4  # user 3's right hand
    assert [h.state for h in right] == [HandState.NEW, HandState.TRACKING, HandState.TOUCHING_FOV, HandState.TRACKING]
