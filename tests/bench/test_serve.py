"""bench.serve's show side: the same profile, its source and backend swapped for `network`."""
from __future__ import annotations

from pathlib import Path

from bench.serve import network_profile
from host import profile as profiles

ROOT = Path(__file__).resolve().parents[2]


def test_the_network_side_keeps_the_profiles_effects_and_output_and_ends_with_the_publisher(tmp_path):
    original = profiles.load(ROOT / "profiles" / "stage.toml")
    served = profiles.load(network_profile(ROOT / "profiles" / "stage.toml", "tcp://127.0.0.1:7001",
                                           tmp_path / "network.toml"))
    assert served.source is None and served.backend.ref.name == "network"
    assert served.backend.options.connect == "tcp://127.0.0.1:7001" and served.backend.options.end_with_publisher
    assert [e.ref.name for e in served.effects] == [e.ref.name for e in original.effects]
    assert served.model.output == original.model.output
