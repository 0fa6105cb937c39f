"""`issv serve` and the `network` backend in separate processes on loopback."""
from __future__ import annotations

import json
import signal
import socket
import subprocess
import sys
import textwrap
import time
from itertools import islice

import numpy as np
import pytest

from backends.network.backend import NetworkBackend, NetworkOptions
from backends.network.command import codec_for
from backends.network.wire import DEFAULT_CODEC
from host import frames_of
from sources.clip import Clip
from tests.backends.engine.performer import swipe_cut_short
from tests.backends.network.conftest import (START_S, ROOT, HelperDied, Serve, clip_profile, free_ports,
                                            wait_for_line)


def subscriber(port: int, **options) -> NetworkBackend:
    return NetworkBackend(None, NetworkOptions(connect=f"tcp://127.0.0.1:{port}", **options))


def test_frames_arrive_whole_depth_bit_exact(serve, tmp_path, performer_clip):
    port = free_ports()
    stats_file = tmp_path / "sent.json"
    server = serve(str(clip_profile(tmp_path, performer_clip, loop=False)), "--bind", f"tcp://127.0.0.1:{port}",
                   "--codec", "banded-zstd", "--stats-json", str(stats_file))  # compressed, though on loopback
    clip = Clip(performer_clip)
    truth = {tuple(p) for row in clip.hands for p in row}
    with subscriber(port, end_with_publisher=True, depth_wait_ms=500) as backend:
        frames = list(frames_of(backend))
        stats = backend.stats()
    assert len(frames) >= 40  # the clip is 132 frames; a late joiner may miss the first few
    with_depth = [f for f in frames if f.depth is not None]
    assert len(with_depth) >= len(frames) - 2
    for f in with_depth:
        assert np.array_equal(f.depth.data, clip.depth[f.depth.frame_id])  # lossless
        assert f.depth.intrinsics == clip.intrinsics
    for f in frames:
        assert f.backend == "truth"
        assert {h.side.value for h in f.hands} == {"left", "right"}
        assert all(h.position in truth for h in f.hands)
    assert stats["streams"]["hands"]["lost"] == 0
    assert stats["streams"]["hands"]["received"] == len(frames)
    server.proc.wait(timeout=20)  # it writes its stats after saying goodbye
    sent = json.loads(stats_file.read_text())
    assert sent["sent"]["hands"] == len(clip) and sent["compression"] > 1


def test_a_swipe_the_clip_ends_on_arrives_before_the_stream_ends(serve, tmp_path):
    """Only the end of the served clip completes the swipe: it still reaches the subscriber, and
    on loopback depth goes raw (uncompressed, sent with the hands) and still exact."""
    port = free_ports()
    clip = swipe_cut_short(tmp_path / "cut.npz")
    stats_file = tmp_path / "sent.json"
    server = serve(str(clip_profile(tmp_path, clip, loop=False, backend="openiss")), "--bind",
                   f"tcp://127.0.0.1:{port}", "--stats-json", str(stats_file))
    with subscriber(port, end_with_publisher=True, depth_wait_ms=500) as backend:
        frames = list(frames_of(backend))
    gestures = [g for f in frames for g in f.gestures]
    assert [g.name for g in gestures if g.state.value == "complete"] == ["swipe_left"]
    depth = Clip(clip).depth
    assert all(np.array_equal(f.depth.data, depth[f.depth.frame_id]) for f in frames if f.depth is not None)
    labelled = [f for f in frames if f.depth is not None and f.user_labels is not None]  # the engine's users
    assert len(labelled) == len([f for f in frames if f.depth is not None])
    assert all(f.user_labels.shape == f.depth.data.shape for f in labelled)
    assert any(f.user_labels.any() for f in labelled)
    server.proc.wait(timeout=20)
    sent = json.loads(stats_file.read_text())
    assert sent["compression"] == 1.0 and sent["depth_skipped"] == 0 and sent["sent"]["depth"] == len(depth)
    assert sent["metrics"]["frames"] == len(depth) and sent["metrics"]["latency_ms"]["p99"] > 0


def test_serve_compresses_depth_unless_bound_to_loopback():
    assert codec_for(None, "tcp://127.0.0.1:5555") == codec_for(None, "tcp://[::1]:5555") == "raw"
    assert codec_for(None, "tcp://localhost:5555") == "raw"
    assert codec_for(None, "tcp://0.0.0.0:5555") == codec_for(None, "tcp://stage-pc:5555") == DEFAULT_CODEC
    assert codec_for("zstd", "tcp://127.0.0.1:5555") == "zstd"  # --codec always wins
    assert codec_for(None, "http://127.0.0.1:11311", "ros") == DEFAULT_CODEC


BURST = textwrap.dedent("""
    import sys, time
    from backends.network.publisher import Publisher, DepthOptions
    from host import Frame, Gesture, GestureState, GestureType, Side
    pub = Publisher(sys.argv[1], DepthOptions(enabled=False), "burst")
    print("burst: bound", file=sys.stderr, flush=True)
    assert pub.wait_for_subscriber(20)
    k = 0
    for i in range(3000):
        gs = []
        for _ in range(3):
            gs.append(Gesture(GestureType.SWIPE_UP, GestureState.COMPLETE, (0.0, 0.0, 1.0), 1, Side.LEFT, 1.0, k))
            k += 1
        pub.publish(Frame(i + 1, time.time(), None, (), tuple(gs), "burst"))
    pub.close()
""")


def test_gestures_arrive_exactly_once_and_in_order_under_a_burst():
    port = free_ports()
    proc = subprocess.Popen([sys.executable, "-c", BURST, f"tcp://127.0.0.1:{port}"], cwd=ROOT,
                            stderr=subprocess.PIPE, text=True)
    wait_for_line(proc, "bound", "the burst publisher")
    try:
        with subscriber(port, end_with_publisher=True) as backend:
            got = [g.timestamp for f in frames_of(backend) for g in f.gestures]
            stats = backend.stats()
    finally:
        proc.wait(timeout=30)
    assert got == list(range(9000))  # every one, once, in order, as fast as Python can send them
    assert stats["streams"]["gestures"]["lost"] == 0 and stats["streams"]["gestures"]["duplicates"] == 0


def test_reconnects_after_the_publisher_restarts_and_says_so_once(serve, tmp_path, capsys, performer_clip):
    port = free_ports()
    profile = str(clip_profile(tmp_path, performer_clip, loop=True))
    first = serve(profile, "--bind", f"tcp://127.0.0.1:{port}")
    with subscriber(port) as backend:
        before = list(islice(frames_of(backend), 10))
        first.kill()  # no goodbye: the hard case
        serve(profile, "--bind", f"tcp://127.0.0.1:{port}")
        after = list(islice(frames_of(backend), 10))
        stats = backend.stats()
    assert len(before) == len(after) == 10
    assert stats["restarts"] == 1
    assert capsys.readouterr().err.count("restarted") == 1


def _port_free(port: int) -> bool:
    with socket.socket() as s:
        try:
            s.bind(("127.0.0.1", port))
            return True
        except OSError:
            return False


def test_serve_and_run_side_by_side_with_no_edits(serve, tmp_path):
    busy = "port 5555 or 5556 is in use on this machine (another issv serve, another test run?)"
    if not (_port_free(5555) and _port_free(5556)):
        pytest.skip(busy)
    try:
        serve("profiles/demo.toml", "--seconds", "30")
    except pytest.fail.Exception as failed:  # taken between the check and the bind
        if "Address already in use" not in str(failed):
            raise
        pytest.skip(busy)
    metrics = tmp_path / "m.json"
    run = subprocess.run([sys.executable, "-m", "host", "run", "profiles/network.toml", "--headless",
                          "--seconds", "2", "--metrics-json", str(metrics)], cwd=ROOT, capture_output=True,
                         text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    m = json.loads(metrics.read_text())
    assert m["backend"] == "network" and m["frames"] >= 30
    assert "hands" in run.stderr and "0 lost" in run.stderr


def test_a_serve_that_cannot_start_fails_the_test_at_once_with_its_stderr(tmp_path):
    began = time.monotonic()
    with pytest.raises(pytest.fail.Exception, match=r"(?s)did not start \(exited.*no-such\.toml"):
        Serve(str(tmp_path / "no-such.toml"))
    assert time.monotonic() - began < START_S


def test_a_serve_that_fails_after_starting_interrupts_a_waiting_subscriber(serve, tmp_path):
    """Its source is missing: it says it is publishing, then fails; the blocked subscriber is freed."""
    port = free_ports()
    serve(str(clip_profile(tmp_path, tmp_path / "gone.npz", loop=False)), "--bind", f"tcp://127.0.0.1:{port}")
    began = time.monotonic()
    with pytest.raises(HelperDied, match="gone.npz"):
        with subscriber(port) as backend:
            next(frames_of(backend))
    assert time.monotonic() - began < START_S


def test_a_helper_that_never_says_it_started_is_stopped_within_the_bound():
    """Even with half a line written and the pipe held open by a child of its own (as roscore's are)."""
    # SIGINT ends the shell, as it ends every helper (issv serve, roscore): a suite started in the
    # background from a non-interactive shell runs with SIGINT ignored, and a shell would inherit that
    proc = subprocess.Popen(["sh", "-c", "sleep 60 & printf 'half a line' >&2; sleep 60"], stderr=subprocess.PIPE,
                            text=True, start_new_session=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    began = time.monotonic()
    with pytest.raises(pytest.fail.Exception, match=r"(?s)said nothing with 'ready' in 1 s.*half a line"):
        wait_for_line(proc, "ready", "the helper", timeout=1)
    assert time.monotonic() - began < 10 and proc.poll() is not None
    time.sleep(0.2)
    table = subprocess.run(["ps", "-eo", "pgid=,stat="], capture_output=True, text=True).stdout.split("\n")
    assert not [row for row in table if row.split()[:1] == [str(proc.pid)] and not row.split()[1].startswith("Z")]
