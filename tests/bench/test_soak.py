"""bench.soak on a few seconds of the demo show: it samples, records, sends OSC and reports."""
from __future__ import annotations

from pathlib import Path

from bench.soak import soak

ROOT = Path(__file__).resolve().parents[2]


def test_a_short_soak_samples_the_show_and_everything_it_made(tmp_path):
    f = soak(ROOT / "profiles" / "demo.toml", seconds=3.0, size=None, sample_s=0.5, warmup_s=1.0, out_dir=tmp_path)
    assert f["frames"] > 10 and f["recorded_frames"] == f["frames"]
    assert f["osc_datagrams"] > 0 and f["recording_mb"] > 0
    assert len(f["samples"]) >= 5 and f["samples"][-1]["frames"] == f["frames"]
    assert f["rss_mb"]["end"] > 10 and f["handles"]["end"] > 0
    assert f["drift"]["first"]["sfps"] > 0 and len(f["windows"]) == len(f["samples"]) - 1
