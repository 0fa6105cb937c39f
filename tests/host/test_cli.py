"""The command-line interfaces other tools rely on: keys and formats are kept exactly."""
import json
import subprocess
import sys
from pathlib import Path

from host import __version__

ROOT = Path(__file__).resolve().parents[2]


def issv(*args, **kw):
    return subprocess.run([sys.executable, "-m", "host", *map(str, args)], capture_output=True, text=True, **kw)


def test_version():
    assert issv("--version").stdout.strip() == f"issv {__version__}"


def test_list_json_shows_the_builtins_with_availability():
    data = json.loads(issv("list", "--json").stdout)
    assert set(data) == {"backends", "sources", "effects"}
    for kind, items in data.items():
        for item in items:
            extra = {"devices"} if kind == "sources" and "devices" in item else set()  # sources opening cameras
            framed = {"frames"} if kind != "effects" else set()  # depth or colour frames (None: its own)
            assert set(item) == {"name", "available", "reason", "plugin"} | extra | framed
            assert (item["reason"] is None) == item["available"]
    frames = {i["name"]: i["frames"] for kind in ("backends", "sources") for i in data[kind]}
    assert frames["openiss"] == frames["synthetic"] == "depth" and frames["osc-in"] is None
    names = {kind: {i["name"] for i in items} for kind, items in data.items()}
    assert {"truth"} <= names["backends"] and {"clip", "synthetic"} <= names["sources"]
    assert "console" in names["effects"]


def test_list_shows_how_to_install_an_extra_verbatim():
    """The reason's `issv[webcam]` is text, not rich markup (which would swallow `[webcam]`)."""
    from rich.console import Console
    from host.commands.list import table
    reason = "MediaPipe is not installed: pip install 'issv[webcam]'"
    console = Console(width=300, record=True)
    console.print(table("backends", [{"name": "mediapipe", "available": False, "plugin": "builtin-backends",
                                      "frames": "colour", "reason": reason}]))
    assert reason in console.export_text()


def test_run_reports_metrics_and_delivers_every_truth_gesture_once(tmp_path):
    from host.profile import load
    from host.assemble import make_backend

    profile = tmp_path / "p.toml"
    profile.write_text('backend = "truth"\n[source]\nname = "synthetic"\nseed = 3\n'
                       '[[effects]]\nname = "console"\nformat = "json"\n[output]\nmode = "headless"\n')
    # What the performer really did, straight from the source.
    source = make_backend(load(profile), realtime=False).source
    source.open()
    truth = set()
    while (depth := source.read()) is not None:
        truth.update(depth.truth.gestures)
    source.close()

    metrics = tmp_path / "m.json"
    run = issv("run", profile, "--headless", "--fast", "--metrics-json", metrics)
    assert run.returncode == 0, run.stderr
    m = json.loads(metrics.read_text())
    assert set(m) == {"backend", "source_fps", "sfps", "rfps", "effective_fps", "latency_ms", "frames", "dropped",
                      "gestures", "gestures_by_name"}
    assert set(m["latency_ms"]) == {"p50", "p95", "p99"}
    events = [json.loads(l) for l in run.stdout.splitlines() if l.startswith("{")]
    completed = [(e["name"], e["side"]) for e in events if e["type"] == "gesture" and e["state"] == "complete"]
    assert sorted(completed) == sorted((g.name, g.side.value) for g in truth)
    assert m["gestures"] == len(truth) == sum(m["gestures_by_name"].values())
