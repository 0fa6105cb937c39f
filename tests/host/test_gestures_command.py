"""`issv gestures FILE.csv`: trajectories in, event lines out (docs/architecture.md formats)."""
from __future__ import annotations

import copy
import json
import subprocess

import pytest

from backends.engine.recognizer import NITE_DICTIONARY, GestureRecognizer
from backends.engine.rules import GestureRules
from host import Backend
from host.cli import main as issv
from host.plugins import default_registry
from tests.backends.engine import choreography as c

EVENT_KEYS = {"t", "type", "name", "native", "state", "hand", "side", "position", "confidence"}


def events(stdout: str) -> list[dict]:
    return [json.loads(line) for line in stdout.splitlines() if line.strip()]


def test_a_swipe_file_gives_one_complete_swipe_line(tmp_path):
    csv = c.swipe().write_csv(tmp_path / "swipe.csv")
    run = subprocess.run(["issv", "gestures", str(csv), "--backend", "openiss", "--mirrored"],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    lines = events(run.stdout)
    assert all(set(e) == EVENT_KEYS and e["type"] == "gesture" for e in lines)
    done = [e for e in lines if e["state"] == "complete"]
    assert [(e["name"], e["native"], e["side"], e["hand"]) for e in done] == [("swipe_left", "SWIPE_LEFT", "right", 2)]
    assert len(done[0]["position"]) == 3 and 0 <= done[0]["confidence"] <= 1
    # the same file read as an unmirrored image: +x is the performer's left, so the swipe is to the right
    run = subprocess.run(["issv", "gestures", str(csv)], capture_output=True, text=True, timeout=120)
    assert [e["name"] for e in events(run.stdout) if e["state"] == "complete"] == ["swipe_right"]


def test_a_file_that_ends_while_a_swipe_is_confirmed_still_gives_it(tmp_path):
    """The file stops within the swipe's confirmation time: its end completes the swipe."""
    performance = c.swipe()
    recognizer = GestureRecognizer(GestureRules())
    for t, hands, body in performance.frames():  # up to the first frame at which the swipe waits
        assert not [g for g in recognizer.update(t, hands, body, True) if g.state.value == "complete"]
        if [g for g in copy.deepcopy(recognizer).finish() if g.state.value == "complete"]:
            waiting = t
            break
    rows = performance.write_csv(tmp_path / "full.csv").read_text()
    header, *body = rows.splitlines()
    cut = tmp_path / "cut.csv"
    cut.write_text("\n".join([header] + [r for r in body if float(r.split(",")[0]) <= waiting + 1e-6]) + "\n")
    run = subprocess.run(["issv", "gestures", str(cut), "--mirrored"], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    lines = events(run.stdout)
    assert [e["name"] for e in lines if e["state"] == "complete"] == ["swipe_left"]
    assert lines[-1]["state"] == "complete"


class NiteOnlyBackend(Backend):
    """A tiny backend of this test: the engine's recogniser in NiTE mode, nothing else."""

    name = "test-nite-only"

    @classmethod
    def recognizer(cls, options=None) -> GestureRecognizer:
        return GestureRecognizer(GestureRules(), NITE_DICTIONARY)


class NoRecognizerBackend(Backend):
    name = "test-no-recognizer"


@pytest.fixture
def test_backends():
    registry = default_registry()
    for cls in (NiteOnlyBackend, NoRecognizerBackend):
        registry.register("backends", cls, "tests")
    yield
    for cls in (NiteOnlyBackend, NoRecognizerBackend):
        registry.items["backends"].pop(cls.name)


def test_the_backend_chooses_the_recogniser_and_its_dictionary(test_backends, tmp_path, capsys):
    assert issv(["gestures", str(c.wave().write_csv(tmp_path / "wave.csv")), "--backend", "test-nite-only",
                 "--mirrored"]) == 0
    assert [(e["name"], e["native"]) for e in events(capsys.readouterr().out)
            if e["state"] == "complete"] == [("wave", "WAVE")]
    assert issv(["gestures", str(c.swipe().write_csv(tmp_path / "swipe.csv")), "--backend", "test-nite-only",
                 "--mirrored"]) == 0
    assert events(capsys.readouterr().out) == []  # NiTE has no swipes


def test_a_backend_without_recogniser_is_refused_by_name(test_backends, tmp_path, capsys):
    csv = c.wave().write_csv(tmp_path / "wave.csv")
    assert issv(["gestures", str(csv), "--backend", "test-no-recognizer"]) == 1
    err = capsys.readouterr().err
    assert "test-no-recognizer" in err and "test-nite-only" in err
    assert issv(["gestures", str(csv), "--backend", "no-such-backend"]) == 1
    assert "no-such-backend" in capsys.readouterr().err


def test_hands_only_files_work_and_integer_ids_are_kept(tmp_path, capsys):
    rows = c.push().write_csv(tmp_path / "push.csv", with_body=False).read_text()
    (tmp_path / "ids.csv").write_text(rows.replace(",left,", ",7,").replace(",right,", ",8,"))
    assert issv(["gestures", str(tmp_path / "ids.csv")]) == 0
    done = [e for e in events(capsys.readouterr().out) if e["state"] == "complete"]
    assert done and {e["name"] for e in done} == {"click"} and {e["hand"] for e in done} <= {7, 8}
    assert {e["side"] for e in done} == {"unknown"}


@pytest.mark.parametrize("text, where, says", [
    ("t,hand,x,y\n0,left,1,2\n", ":1:", "lacks z"),
    ("t,hand,x,y,z\n0,left,1,2,3\n0,right,abc,2,3\n", ":3:", "column x must be a number"),
    ("t,hand,x,y,z\n0,left,1,2,3\n0.1,elbow,1,2,3\n", ":3:", "hand must be"),
    ("t,hand,x,y,z\n0.1,left,1,2,3\n0.0,left,1,2,3\n", ":3:", "back in time"),
])
def test_a_bad_file_is_one_clear_line_naming_file_and_line(tmp_path, capsys, text, where, says):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    assert issv(["gestures", str(path)]) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"{path}{where}") and says in err and len(err.splitlines()) == 1


def test_a_missing_file_is_named(tmp_path, capsys):
    assert issv(["gestures", str(tmp_path / "nope.csv")]) == 1
    assert "nope.csv" in capsys.readouterr().err


def test_a_binary_file_is_named_as_no_text_csv(tmp_path, capsys):
    path = tmp_path / "take.csv"
    path.write_bytes(b"PK\x03\x04\xff\xfe\x00" * 50)  # a zip (a .npz clip) given where a CSV belongs
    assert issv(["gestures", str(path)]) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"{path}: not a text CSV of t,hand,x,y,z rows") and len(err.splitlines()) == 1
