"""A show whose publisher is not there (a mistyped host, a camera machine started later): it says
where it waits and what to start, keeps a time limit in wall time, stops on a signal, and picks up
a publisher that starts late. Real `issv run` and `issv serve` processes on free loopback ports."""
from __future__ import annotations

import json
import signal
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from backends.network.command import how_to_serve
from tests.backends.network.conftest import ROOT, START_S, clip_profile, free_ports, stop, wait_for_line
from tests.backends.network.test_loopback import subscriber

WAITING = "no publisher at"


def network_profile(tmp: Path, port: int, end_with_publisher: bool = False) -> Path:
    path = tmp / "show.toml"
    path.write_text(f'[backend]\nname = "network"\nconnect = "tcp://127.0.0.1:{port}"\n'
                    f'end_with_publisher = {str(end_with_publisher).lower()}\n'
                    '[[effects]]\nname = "console"\n[output]\nmode = "headless"\n')
    return path


@contextmanager
def run(profile: Path, *args: str) -> Iterator[subprocess.Popen]:
    """`issv run PROFILE --headless ARGS`, stopped if a failed assertion leaves it running."""
    proc = subprocess.Popen([sys.executable, "-m", "host", "run", str(profile), "--headless", "--no-reload", *args],
                            cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        yield proc
    finally:
        stop(proc)


def test_a_subscriber_with_no_publisher_answers_nothing_yet_and_says_where_to_start_one():
    port = free_ports()
    with subscriber(port) as backend:
        assert backend.update() is False  # a short poll, not a wait for ever
        assert backend.input_label() == (f"no publisher at tcp://127.0.0.1:{port} yet (start one on this machine: "
                                         f"issv serve PROFILE --bind tcp://127.0.0.1:{port})")


def test_the_publisher_to_start_is_bound_where_the_show_can_reach_it():
    assert how_to_serve("tcp://stage-pc:5600") == "on stage-pc: issv serve PROFILE --bind tcp://0.0.0.0:5600"
    assert how_to_serve("tcp://[::1]:5555") == "on this machine: issv serve PROFILE --bind tcp://[::1]:5555"
    assert how_to_serve("http://cam:11311", "/openiss") == \
        "on the camera machine: issv serve PROFILE --transport ros --bind http://cam:11311 --namespace /openiss"


def test_run_with_seconds_ends_with_one_line_naming_the_endpoint_when_no_publisher_comes(tmp_path):
    port = free_ports()
    with run(network_profile(tmp_path, port), "--seconds", "2") as proc:
        _, err = proc.communicate(timeout=30)  # a liveness bound for a loaded machine: the limit is 2 + 5 s
    endpoint = f"tcp://127.0.0.1:{port}"
    assert proc.returncode == 1, err
    assert f"issv: network: {WAITING} {endpoint} yet" in err  # said at 2 s, while it waited
    last = err.strip().splitlines()[-1]
    assert last.startswith("backend 'network': no frame in 7 s") and f"--bind {endpoint}" in last
    assert "Traceback" not in err


def test_without_a_limit_it_waits_and_a_signal_still_ends_it(tmp_path):
    with run(network_profile(tmp_path, free_ports())) as proc:
        wait_for_line(proc, WAITING, "issv run")
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=30)
    assert proc.returncode == 0, err
    assert "Traceback" not in err


def test_a_publisher_that_starts_after_the_show_is_picked_up(serve, tmp_path, performer_clip):
    port = free_ports()
    metrics = tmp_path / "m.json"
    with run(network_profile(tmp_path, port, end_with_publisher=True), "--metrics-json", str(metrics)) as proc:
        wait_for_line(proc, WAITING, "issv run")
        serve(str(clip_profile(tmp_path, performer_clip, loop=False)), "--bind", f"tcp://127.0.0.1:{port}")
        _, err = proc.communicate(timeout=START_S + 30)  # the clip is 4.4 s; its end ends the show
    assert proc.returncode == 0, err
    assert f"publisher at tcp://127.0.0.1:{port} found; receiving" in err
    assert json.loads(metrics.read_text())["frames"] >= 40  # of 132; a late joiner may miss the first few
