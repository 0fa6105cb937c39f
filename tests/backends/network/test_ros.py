"""ROS interop against a real roscore: `issv serve --transport ros` publishes the thesis' topics,
the `network` backend with transport = "ros" subscribes (as openiss/DepthFrame and as
sensor_msgs/Image)."""
from __future__ import annotations

import json
import os
import subprocess
import sys
import time

import numpy as np
import pytest

from backends.network.ros import rospy_missing
from sources.clip import Clip
from tests.backends.network.conftest import ROOT, Serve, clip_profile, free_ports, stop, wait_for_line
from tests.backends.network.test_labels import assert_duet_labels_arrived, duet_profile, received, subscribe
from tests.backends.network.test_users import duet
from tests.backends.oscin.helpers import replay

REASON = rospy_missing()
ROSCORE_START_S = 90  # roslaunch, rosmaster and rosout: slow to start on a loaded machine
pytestmark = pytest.mark.skipif(REASON is not None, reason=f"ROS: {REASON}")


@pytest.fixture
def roscore():
    port = free_ports(1)
    master = f"http://127.0.0.1:{port}"
    env = {**os.environ, "ROS_MASTER_URI": master, "ROS_IP": "127.0.0.1", "ROS_HOME": "/tmp/issv-ros-test"}
    core = subprocess.Popen(["roscore", "-p", str(port)], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, start_new_session=True)
    try:
        wait_for_line(core, "started core service", "roscore", ROSCORE_START_S, stream=core.stdout)
        yield env
    finally:
        stop(core, grace=15)


def serve_to_ros_subscribers(roscore: dict, tmp_path, profile, seconds: float) -> dict[str, tuple[str, str]]:
    """`issv serve --transport ros` of `profile` for `seconds`, to two subscriber processes subscribed
    before it starts (openiss/DepthFrame and sensor_msgs/Image depth, dumped to tmp_path/KIND.npz):
    {kind: (stdout, stderr)}."""
    master = roscore["ROS_MASTER_URI"]
    subs = {kind: subscribe(tmp_path, master, "--transport", "ros", "--ros-depth", kind, env=roscore, name=kind)
            for kind in ("frame", "image")}
    server = Serve(str(profile), "--transport", "ros", "--bind", master, "--seconds", str(seconds), env=roscore)
    try:
        return {k: p.communicate(timeout=90) for k, p in subs.items()}
    finally:
        server.stop()
        for p in subs.values():
            if p.poll() is None:
                p.kill()


def test_serve_over_ros_to_the_network_backend(roscore, tmp_path, performer_clip):
    results = serve_to_ros_subscribers(roscore, tmp_path, clip_profile(tmp_path, performer_clip, loop=True), 4)
    clip = Clip(performer_clip)
    for kind, (out, err) in results.items():
        got = json.loads(out.strip().splitlines()[-1])
        streams = got["streams"]
        assert got["frames"] >= 40, err
        assert streams["hands"]["lost"] == 0 and got["malformed"] == {}, err
        dump = np.load(tmp_path / f"{kind}.npz")
        assert len(dump["depth"]) >= 40
        if kind == "frame":  # openiss/DepthFrame carries frame ids: compare image for image
            for i, data in zip(dump["frame_ids"], dump["depth"]):
                assert np.array_equal(data, clip.depth[i % len(clip)])  # the clip loops
        else:  # sensor_msgs/Image: every image is one of the clip's, bit for bit
            for data in dump["depth"]:
                assert any(np.array_equal(data, c) for c in clip.depth)


SUBSCRIBE_USERS = """
import json, sys
from backends.network.backend import NetworkBackend, NetworkOptions
from host import frames_of
options = NetworkOptions(transport="ros", connect=sys.argv[1], depth=False, end_with_publisher=True)
with NetworkBackend(None, options) as backend:
    print("subscribed", file=sys.stderr, flush=True)
    frames = list(frames_of(backend))
print(json.dumps([{"backend": f.backend, "users": [u.to_json() for u in f.users],
                   "hands": [[h.user_id, h.extended, h.state.value] for h in f.hands],
                   "gestures": [[g.name, g.user_id] for g in f.gestures]} for f in frames]))
"""


def test_users_over_ros_in_the_hands_topic(roscore, tmp_path):
    """osc-in in `issv serve --transport ros`, fed a duet by `issv osc-replay`; a subscriber process."""
    master = roscore["ROS_MASTER_URI"]
    session, profile, osc_port = duet(tmp_path)
    sub = subprocess.Popen([sys.executable, "-c", SUBSCRIBE_USERS, master], cwd=ROOT, env=roscore,
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        wait_for_line(sub, "subscribed", "the ROS users subscriber")
        server = Serve(str(profile), "--transport", "ros", "--bind", master, env=roscore)
        try:
            time.sleep(2.0)  # rospy connects publisher and subscriber on its own threads
            sender = replay(session, osc_port)
            assert sender.wait(60) == 0, sender.stderr.read()
            out, err = sub.communicate(timeout=60)
        finally:
            server.stop()
    finally:
        if sub.poll() is None:
            sub.kill()
    got = json.loads(out.strip().splitlines()[-1])
    with_users = [f for f in got if f["users"]]
    assert len(with_users) >= 30, err
    assert {tuple(sorted(u["id"] for u in f["users"])) for f in with_users} >= {(1,), (1, 2)}
    user2 = next(u for f in with_users for u in f["users"] if u["id"] == 2)
    assert user2["joints"]["torso"]["position"] == pytest.approx([900.0, 0.0, 2100.0], abs=0.01)
    assert user2["center_of_mass"] is not None
    assert all(extended in (True, False) for f in with_users for _, extended, _ in f["hands"])
    assert {user for f in got for _, user in f["gestures"]} <= {1, 2}


def test_the_duet_labels_arrive_over_ros_with_their_depth_images(roscore, tmp_path):
    """`issv serve --transport ros` of the synthetic duet: <ns>/user_labels (mono8) joins each depth
    image, as openiss/DepthFrame and as sensor_msgs/Image, in subscriber processes; the labels equal
    those sent, pixel for pixel."""
    results = serve_to_ros_subscribers(roscore, tmp_path, duet_profile(tmp_path), 5)
    for kind, (out, err) in results.items():
        got = json.loads(out.strip().splitlines()[-1])
        assert got["malformed"] == {}, err
        assert_duet_labels_arrived(received(tmp_path / f"{kind}.npz"), late=True)
