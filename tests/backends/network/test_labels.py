"""The user label image on the wire: in the depth message of its frame, shaped as the depth image."""
from __future__ import annotations

import json
import subprocess
import sys
from dataclasses import replace
from functools import cache
from pathlib import Path

import numpy as np
import pytest

from backends.network import wire
from backends.network.backend import NetworkBackend, NetworkOptions
from backends.network.publisher import DepthOptions
from backends.truth import TruthBackend
from host import DepthFrame, Frame, Intrinsics
from sources.synthetic import SyntheticOptions, SyntheticSource
from tests.backends.network.conftest import ROOT, free_ports, wait_for_line


def two_users(shape=(48, 64)) -> np.ndarray:
    labels = np.zeros(shape, np.uint8)
    labels[10:40, 5:20] = 1
    labels[5:45, 30:50] = 2
    labels[20:30, 15:35] = 1  # the near one in front of the far one
    return labels


def depth_frame(shape=(48, 64)) -> DepthFrame:
    data = np.arange(shape[0] * shape[1], dtype=np.uint16).reshape(shape)
    return DepthFrame(data, Intrinsics(50.0, 50.0, 32.0, 24.0), frame_id=7, timestamp=1.25, capture_time=1000.5)


@pytest.mark.parametrize("codec", sorted(wire.CODECS))
def test_labels_ride_in_the_depth_message_exactly(codec):
    depth, labels = depth_frame(), two_users()
    data = wire.encode_depth(9, 3, depth.capture_time, 12, depth, codec, labels=labels)
    assert wire.HEADER.unpack_from(data)[3] == wire.LABELS and 0 < wire.labels_size(data) < labels.nbytes
    msg = wire.decode(data)
    assert np.array_equal(msg.labels, labels) and msg.labels.dtype == np.uint8
    assert np.array_equal(msg.depth.data, depth.data)


def test_a_depth_message_without_labels_is_unflagged_and_decodes_without_them():
    data = wire.encode_depth(9, 3, 1000.5, 12, depth_frame())
    assert wire.HEADER.unpack_from(data)[3] == 0 and wire.labels_size(data) == 0
    assert wire.decode(data).labels is None


def test_a_version_2_depth_message_is_still_read():
    """What an issv before labels sent: version 2, flags 0, the image right after the fixed block."""
    data = bytearray(wire.encode_depth(9, 3, 1000.5, 12, depth_frame(), "zstd"))
    data[4] = 2
    msg = wire.decode(bytes(data))
    assert msg.labels is None and np.array_equal(msg.depth.data, depth_frame().data)


def test_labels_of_another_size_are_refused_at_the_sender():
    with pytest.raises(ValueError, match="user labels of shape"):
        wire.encode_depth(9, 3, 1000.5, 12, depth_frame(), labels=two_users((24, 32)))


@pytest.mark.parametrize("damage", ["short", "codec", "size", "bomb"])
def test_broken_labels_are_refused_as_bad_labels(damage):
    depth = depth_frame()
    good = wire.encode_depth(9, 3, 1000.5, 12, depth, "zstd", labels=two_users())
    at = wire.HEADER.size + wire.DEPTH_BODY.size
    data = bytearray(good)
    if damage == "short":
        data = data[:at + 2]
    elif damage == "codec":
        data[at] = 9
    elif damage == "size":
        wire.LABELS_BLOCK.pack_into(data, at, wire.LABELS_ZSTD, len(good))
    else:  # a label image far larger than the depth image it claims to go with
        bomb = wire._zstd_in(np.zeros((2000, 2000), np.uint8))
        data = data[:at] + wire.LABELS_BLOCK.pack(wire.LABELS_ZSTD, len(bomb)) + bomb
    with pytest.raises(wire.WireError) as error:
        wire.decode(bytes(data))
    assert error.value.kind == "bad-labels"


def test_labels_are_cropped_and_downscaled_as_depth_is():
    labels = two_users()
    frame = Frame(1, 1000.5, depth_frame(), make_user_labels=lambda: labels)
    options = DepthOptions(crop=(4, 2, 40, 30), downscale=2)
    sent = options.labels_of(frame)()
    assert sent.shape == options.shape(frame.depth).data.shape
    assert np.array_equal(sent, labels[2:32, 4:44][::2, ::2])
    assert DepthOptions(labels=False).labels_of(frame) is None
    assert DepthOptions().labels_of(Frame(1, 1000.5, depth_frame())) is None  # the backend knows no users


def test_labels_apart_from_their_depth_image_join_it_by_capture_time():
    """ROS carries them on a topic of their own: either may come first; a frame waits for both
    (here through the backend's own steps, the messages made as the ROS subscriber makes them)."""
    port = free_ports()
    labels = two_users()
    with NetworkBackend(None, NetworkOptions(connect=f"tcp://127.0.0.1:{port}", depth_wait_ms=1000)) as backend:
        for seq, labels_first in ((1, True), (2, False)):
            capture = 1000.0 + seq
            depth = wire.DepthMsg(wire.Header(wire.DEPTH, 5, seq, capture), seq,
                                  replace(depth_frame(), capture_time=capture))
            apart = wire.LabelsMsg(wire.Header(wire.DEPTH, 5, seq, capture), labels * seq)
            hands = wire.HandsMsg(wire.Header(wire.HANDS, 5, seq, capture), seq, 0.0, "truth", (), True)
            backend._take(hands)
            first, second = (apart, depth) if labels_first else (depth, apart)
            backend._take(first)
            if not labels_first:  # once a session sent labels apart, its frames wait for them
                assert backend._ready() is None
            backend._take(second)
            frame = backend._ready()
            assert frame is not None and np.array_equal(frame.user_labels, labels * seq)
        stale = wire.LabelsMsg(wire.Header(wire.DEPTH, 5, 9, 999.0), labels)  # of an image never shown
        backend._take(stale)
        assert np.array_equal(backend._labels, labels * 2)


DUET = 'name = "synthetic"\nscene = "duet"\nseed = 3\nwidth = 320\nheight = 240\n'


def duet_profile(tmp: Path, backend: str = "truth") -> Path:
    path = tmp / "duet.toml"
    path.write_text(f'[source]\n{DUET}[backend]\nname = "{backend}"\n')
    return path


@cache
def sent_duet(frames: int) -> dict[int, tuple[np.ndarray, np.ndarray]]:
    """frame_id -> (depth, user labels) as `issv serve` of duet_profile() makes them."""
    source = SyntheticSource(SyntheticOptions(scene="duet", seed=3, width=320, height=240))
    out = {}
    with TruthBackend(source) as backend:
        for _ in range(frames):
            f = backend.update()
            out[f.depth.frame_id] = (f.depth.data, f.user_labels)
    return out


def received(dump: Path) -> list[tuple[int, np.ndarray, np.ndarray | None]]:
    """(frame id, depth, labels or None) of each depth image a `bench.network subscribe --dump` got."""
    d = np.load(dump)
    return [(int(i), depth, labels if has else None)
            for i, depth, has, labels in zip(d["frame_ids"], d["depth"], d["has_labels"], d["labels"])]


def assert_duet_labels_arrived(got, downscale: int = 1, late: bool = False) -> None:
    """Every image came with its own labels: the same users' ids on the same pixels as were sent.
    With `late` (ROS, where labels have a topic of their own): but for those before the first that
    did (rospy connects each topic on its own, the labels' up to a second after depth's on a busy
    machine) and a few (up to one in ten) whose labels came later than the frame could wait for them. Images without a
    frame id (ROS's sensor_msgs/Image) are found among those sent by their pixels."""
    sent = sent_duet(max(200, max(i for i, _, _ in got) + 1))
    by_depth = {depth[::downscale, ::downscale].tobytes(): labels for depth, labels in sent.values()}
    first = next((n for n, (_, _, labels) in enumerate(got) if labels is not None), len(got))
    assert first == 0 or late, "the first images came without labels"
    got = got[first:]
    without = [n for n, (_, _, labels) in enumerate(got) if labels is None]
    assert len(without) <= (len(got) // 10 if late else 0), f"images without labels: {without}"  # 7 in 130 seen loaded
    assert len(got) - len(without) >= 40
    got = [g for g in got if g[2] is not None]
    for frame_id, depth, labels in got:
        labels_sent = by_depth.get(depth.tobytes())
        assert labels_sent is not None, f"image {frame_id} is none of those sent"
        if frame_id:
            assert labels_sent is sent[frame_id][1]
        assert np.array_equal(labels, labels_sent[::downscale, ::downscale])
    assert {1, 2} <= set(np.unique(np.concatenate([labels.ravel() for _, _, labels in got])))


def subscribe(tmp: Path, connect: str, *extra: str, env: dict | None = None, name: str = "got") -> subprocess.Popen:
    """`bench.network subscribe` (the network backend in a process of its own), dumping to tmp/NAME.npz."""
    proc = subprocess.Popen([sys.executable, "-m", "bench.network", "subscribe", "--connect", connect,
                             "--timeout", "60", "--dump", str(tmp / f"{name}.npz"), *extra],
                            cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wait_for_line(proc, "subscribed", f"the subscriber {name}")
    return proc


def test_the_duet_labels_cross_zeromq_between_processes_compressed_and_downscaled(serve, tmp_path):
    """`issv serve` (synthetic duet, truth backend) -> a subscriber process: labels equal what was sent."""
    port = free_ports()
    sub = subscribe(tmp_path, f"tcp://127.0.0.1:{port}")
    stats = tmp_path / "sent.json"
    server = serve(str(duet_profile(tmp_path)), "--bind", f"tcp://127.0.0.1:{port}", "--codec", "banded-zstd",
                   "--downscale", "2", "--seconds", "3", "--stats-json", str(stats))
    try:
        out, err = sub.communicate(timeout=90)
    finally:
        if sub.poll() is None:
            sub.kill()
    assert sub.returncode == 0, err
    assert json.loads(out.strip().splitlines()[-1])["malformed"] == {}, err
    assert_duet_labels_arrived(received(tmp_path / "got.npz"), downscale=2)
    server.proc.wait(timeout=20)
    sent = json.loads(stats.read_text())
    assert sent["labels_sent"] == sent["sent"]["depth"] > 0
    assert 0 < sent["labels_bytes"] / sent["labels_sent"] < 160 * 120 / 4  # compressed: well under raw


def test_no_labels_sends_depth_alone(serve, tmp_path):
    port = free_ports()
    sub = subscribe(tmp_path, f"tcp://127.0.0.1:{port}")
    serve(str(duet_profile(tmp_path)), "--bind", f"tcp://127.0.0.1:{port}", "--no-labels", "--seconds", "1.5")
    try:
        sub.communicate(timeout=90)
    finally:
        if sub.poll() is None:
            sub.kill()
    got = received(tmp_path / "got.npz")
    assert got and all(labels is None for _, _, labels in got)
