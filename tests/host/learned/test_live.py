"""Live teaching from a profile: the synthetic performer (issv's own source) raising a hand twice,
its truth hands as the backend; the command counts in, takes each repetition and learns."""
from __future__ import annotations

from host.cli import main as issv
from host.learned import gesture_file, live


def _step(action: str, duration: float, hand: str | None = None) -> str:
    return f'[[steps]]\naction = "{action}"\nduration = {duration}\n' + (f'hand = "{hand}"\n' if hand else "")


# rest, a swipe up, rest, a swipe up, rest: timed so each lands in one live take (2 s count-in, 3 s to perform)
CHOREOGRAPHY = "".join([_step("idle", 2.3), _step("swipe_up", 1.75, "right"), _step("idle", 3.75),
                        _step("swipe_up", 1.75, "right"), _step("idle", 3.5)])

PROFILE = """
[source]
name = "synthetic"
choreography_file = "steps.toml"
[backend]
name = "truth"
"""


def _teach_twice(tmp_path) -> list[str]:
    """`issv learn up` taking two repetitions live from the synthetic profile (written to tmp_path)."""
    (tmp_path / "steps.toml").write_text(CHOREOGRAPHY)
    (tmp_path / "teach.toml").write_text(PROFILE)
    return ["learn", "up", "--profile", str(tmp_path / "teach.toml"), "--repetitions", "2",
            "-o", str(tmp_path / "up.gesture.json")]


def test_live_teaching_takes_the_repetitions_from_the_profile_and_teaches_a_file_more(tmp_path, capsys):
    out = tmp_path / "up.gesture.json"
    assert issv(_teach_twice(tmp_path)) == 0
    said = capsys.readouterr().out
    assert "repetition 1/2: stand still" in said and "repetition 2/2: go!" in said
    learned = gesture_file.load(out)
    assert learned.name == "up" and len(learned.repetitions) == 2 and learned.hands == "right"

    more = tmp_path / "more.gesture.json"
    assert issv(["learn", "up", str(out), "--profile", str(tmp_path / "teach.toml"), "--repetitions", "2",
                 "-o", str(more)]) == 0
    assert f"{out}: 2 repetitions taught before" in capsys.readouterr().out
    sources = [r.source for r in gesture_file.load(more).repetitions]
    assert len(sources) == 4 and len(set(sources)) == 4, "a new session's repetitions are told from the file's"


def test_a_recording_is_an_example_too(tmp_path, capsys):
    (tmp_path / "steps.toml").write_text(CHOREOGRAPHY)
    (tmp_path / "show.toml").write_text(PROFILE)
    recording = tmp_path / "show.mcap"
    assert issv(["record", str(tmp_path / "show.toml"), "-o", str(recording), "--fast"]) == 0
    capsys.readouterr()
    out = tmp_path / "up.gesture.json"
    assert issv(["learn", "up", f"{recording}@0-20", "-o", str(out)]) == 0
    assert f"{recording}@0-20: 2 repetitions found" in capsys.readouterr().out
    assert gesture_file.load(out).hands == "right"


def test_the_bars_are_redrawn_as_they_fill_at_a_terminal_and_said_once_elsewhere(tmp_path, capsys, monkeypatch):
    """A log of `issv learn --profile` holds one line a bar, not one redraw a frame; a terminal sees
    each bar redrawn at most once a step of its width."""
    args = _teach_twice(tmp_path)
    assert issv(args) == 0
    logged = capsys.readouterr().out
    assert "\r" not in logged and logged.count("repetition 1/2: go!") == 1

    monkeypatch.setattr("sys.stdout.isatty", lambda: True)
    assert issv(args) == 0
    redrawn = capsys.readouterr().out.count("\rrepetition 1/2: go!")
    assert 2 <= redrawn <= live.BAR_WIDTH + 1
