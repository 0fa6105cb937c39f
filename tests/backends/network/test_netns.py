"""Two network namespaces joined by a veth pair shaped to 100 Mbit/s (tc tbf): `issv serve` on one
side, the `network` backend on the other, as on two machines."""
from __future__ import annotations

import json
import subprocess
import sys

import pytest

from bench.network import LinkPair
from tests.backends.network.conftest import ROOT, Serve

REASON = LinkPair.unavailable()
pytestmark = pytest.mark.skipif(REASON is not None, reason=f"network namespaces: {REASON}")


def test_serve_across_a_100_mbit_link(tmp_path):
    with LinkPair("100mbit") as link:
        addr = f"tcp://{link.ip_a}:5555"
        sub = subprocess.Popen([*link.prefix("b"), sys.executable, "-m", "bench.network", "subscribe",
                                "--connect", addr, "--timeout", "40"], cwd=ROOT, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
        server = Serve("profiles/demo.toml", "--bind", addr, "--seconds", "4", "--stats-json",
                       str(tmp_path / "sent.json"), prefix=tuple(link.prefix("a")))
        try:
            out, err = sub.communicate(timeout=60)
        finally:
            server.stop()
            if sub.poll() is None:
                sub.kill()
    got = json.loads(out.strip().splitlines()[-1])
    sent = json.loads((tmp_path / "sent.json").read_text())
    streams = got["streams"]
    assert got["frames"] >= 60, err
    assert streams["hands"]["lost"] == 0 and streams["gestures"]["lost"] == 0
    # a late joiner misses the start; from its first message on, nothing is missing, up to the last
    # one the publisher announced in its goodbye
    assert 60 <= streams["hands"]["received"] <= sent["sent"]["hands"]
    assert streams["depth"]["received"] >= 0.9 * streams["hands"]["received"]
    assert got["malformed"] == {}


def test_link_pair_cleans_up_after_itself():
    link = LinkPair("100mbit")
    with link:
        names = subprocess.run(["ip", "netns", "list"], capture_output=True, text=True).stdout
        assert link.ns_a in names and link.ns_b in names
    names = subprocess.run(["ip", "netns", "list"], capture_output=True, text=True).stdout
    assert link.ns_a not in names and link.ns_b not in names
