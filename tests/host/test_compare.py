"""`issv compare`: every backend on the same recorded depth, a report that names them all."""
from __future__ import annotations

import json

import matplotlib.image
import pytest

from host import Gesture, GestureState, GestureType
from host.cli import main as issv
from host.compare import agreement, run_backend
from host.report import coverage_matrix
from tests.recordings import record

BACKENDS = ["truth", "replay", "openiss", "openiss-nite"]


@pytest.fixture(scope="module")
def compared(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("compare")
    recording = record(tmp, seconds=4.0)
    out = tmp / "report"
    assert issv(["compare", str(recording), "--backends", ",".join(BACKENDS), "-o", str(out)]) == 0
    return recording, out


def test_the_report_names_every_backend_and_has_its_plots(compared):
    _, out = compared
    text = (out / "report.md").read_text()
    summary = text.split("## Summary")[1].split("##")[0]
    for name in BACKENDS:
        assert f"| `{name}` |" in summary
    for png in ("gestures.png", "fps.png", "latency.png", "coverage.png", "agreement.png"):
        assert f"]({png})" in text
        image = matplotlib.image.imread(out / png)
        assert image.shape[0] > 100 and image.shape[1] > 100 and image.std() > 0  # a real picture


def test_every_backend_saw_the_whole_recording_and_replay_agrees_with_truth(compared):
    _, out = compared
    text = (out / "report.md").read_text()
    rows = {line.split("|")[1].strip(" `"): line.split("|")[2].strip()
            for line in text.split("## Summary")[1].split("##")[0].splitlines() if line.startswith("| `")}
    assert len(set(rows.values())) == 1 and int(rows["truth"]) > 100  # identical input: same frame count
    agree = text.split("## Agreement between backends")[1]
    truth_row = next(line for line in agree.splitlines() if line.startswith("| `truth`"))
    assert truth_row.split("|")[3].strip() == "1.00"  # recorded with truth: the replay is the same gestures
    events = [json.loads(line) for line in (out / "gestures.jsonl").read_text().splitlines()]
    assert {e["backend"] for e in events if e["state"] == "complete"} >= {"truth", "replay"}


def test_a_backend_that_cannot_run_is_reported_and_the_others_go_on(compared, tmp_path):
    recording, _ = compared
    out = tmp_path / "r"
    assert issv(["compare", str(recording), "--backends", "network,truth", "-o", str(out)]) == 0
    text = (out / "report.md").read_text()
    assert "**`network` failed**: backend 'network' does not read depth" in text and "| `truth` |" in text


def test_unknown_backends_are_refused_before_anything_runs(compared, tmp_path, capsys):
    recording, _ = compared
    assert issv(["compare", str(recording), "--backends", "truth,nite3", "-o", str(tmp_path / "r")]) == 1
    assert "unknown backend 'nite3'" in capsys.readouterr().err and not (tmp_path / "r").exists()


def g(name: str, state: str, t: float, hand: int = 1) -> Gesture:
    return Gesture(GestureType.from_canonical(name), GestureState(state), (0, 0, 2000), hand, timestamp=t)


def test_agreement_matches_gestures_whose_spans_meet():
    performed = [g("wave", "in_progress", 1.9), g("wave", "complete", 3.5), g("click", "complete", 6.0)]
    early = [g("wave", "complete", 2.7), g("click", "complete", 6.4)]  # completes half-way through the wave
    assert agreement(performed, early) == (2, 1.0)
    assert agreement(performed, [g("swipe_left", "complete", 3.0)]) == (0, 0.0)
    assert agreement(performed, [g("click", "complete", 6.3)]) == (1, pytest.approx(2 / 3))
    assert agreement(performed, [g("click", "complete", 7.0)]) == (0, 0.0)  # 1 s late: outside the 0.5 s window
    assert agreement([], []) == (0, None)


def test_coverage_marks_gestures_outside_a_backends_dictionary(compared):
    recording, _ = compared
    nite = run_backend("openiss-nite", recording)
    assert nite.error is None and nite.dictionary == ("click", "hand_raise", "wave")
    row = coverage_matrix([nite])[0]
    assert [str(v) for v in row[3:]] == ["nan"] * 4  # the swipes: not in NiTE's dictionary
