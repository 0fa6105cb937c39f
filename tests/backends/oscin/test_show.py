"""Same show, any input: profiles/stage.toml with only its backend line changed runs on osc-in."""
import json
import subprocess
import sys

from bench.osc import free_port
from tests.backends.oscin.helpers import ROOT, body_at, env, hands_at, replay, write_session


def test_the_stage_profile_runs_on_osc_in_with_its_effects(tmp_path):
    frames = [hands_at(1, i) for i in range(60)] + [[]]
    session = write_session(tmp_path / "s.txt", frames, bodies=[body_at(1)] * 60 + [{}])
    session.write_text("3000" + session.read_text()[1:])  # the first line waits 3 s: the show starts meanwhile
    text = (ROOT / "profiles" / "stage.toml").read_text()
    port = free_port()
    profile = tmp_path / "stage.toml"
    profile.write_text(text.replace('[backend]\nname = "openiss"',
                                    f'[backend]\nname = "osc-in"\nport = {port}\nend_after_idle_s = 1.0'))
    metrics, snapshot = tmp_path / "m.json", tmp_path / "last.png"
    show = subprocess.Popen([sys.executable, "-m", "host", "run", str(profile), "--headless", "--size", "320x180",
                             "--metrics-json", str(metrics), "--snapshot", str(snapshot)],
                            cwd=ROOT, env=env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    sender = replay(session, port)
    out, err = show.communicate(timeout=120)
    assert sender.wait(30) == 0 and show.returncode == 0, err
    assert "is not used: backend 'osc-in' makes its own frames" in err  # the profile's [source]
    assert "that effect is skipped" not in err  # a source warning, not an effect one
    assert "disabled" not in err and "Traceback" not in err  # every effect ran on osc-in's frames
    m = json.loads(metrics.read_text())
    assert m["backend"] == "osc-in" and m["frames"] > 20 and m["gestures_by_name"].get("swipe_right") == 1
    assert snapshot.stat().st_size > 0


def test_issv_record_and_compare_on_osc_in(tmp_path):
    """`issv record` on an osc-in profile (a session sent by `issv osc-replay`), then `issv compare`
    on the recording: the recorded tracks (`replay`) give the user, hands and gestures osc-in found."""
    frames = [hands_at(1, i) for i in range(60)] + [[]]
    session = write_session(tmp_path / "s.txt", frames, bodies=[body_at(1)] * 60 + [{}])
    session.write_text("2000" + session.read_text()[1:])  # the recorder starts meanwhile
    port = free_port()
    profile = tmp_path / "osc.toml"
    profile.write_text(f'[backend]\nname = "osc-in"\nport = {port}\nend_after_idle_s = 1.0\n')
    recording = tmp_path / "osc.mcap"
    record = subprocess.Popen([sys.executable, "-m", "host", "record", str(profile), "-o", str(recording)],
                              cwd=ROOT, env=env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    sender = replay(session, port, "--time-tags")
    _, err = record.communicate(timeout=120)
    assert sender.wait(30) == 0 and record.returncode == 0, err
    from host.recording import Recording
    with Recording(recording) as rec:
        recorded = list(rec.frames())
    assert sum(1 for f in recorded if f.users) > 40 and recorded[0].users[0].state.value == "new"
    swipes = [g for f in recorded for g in f.gestures if g.name == "swipe_right" and g.state.value == "complete"]
    assert [(g.user_id, g.hand_id) for g in swipes] == [(1, 12)]
    out = tmp_path / "cmp"
    compare = subprocess.run([sys.executable, "-m", "host", "compare", str(recording), "--backends", "replay",
                              "-o", str(out)], cwd=ROOT, env=env(), capture_output=True, text=True, timeout=120)
    assert compare.returncode == 0, compare.stderr
    assert "backend `osc-in`" in (out / "report.md").read_text()
    events = [json.loads(line) for line in (out / "gestures.jsonl").read_text().splitlines()]
    assert [(e["backend"], e["name"], e["hand"]) for e in events if e["state"] == "complete"] == [
        ("replay", "swipe_right", 12)]


def test_a_show_with_a_time_limit_ends_when_no_bridge_ever_sends(tmp_path):
    """No sender (a bridge not started): `--seconds 1` still ends, saying which port it listened on."""
    port = free_port()
    profile = tmp_path / "quiet.toml"
    profile.write_text(f'[backend]\nname = "osc-in"\nport = {port}\n[output]\nmode = "headless"\n')
    show = subprocess.run([sys.executable, "-m", "host", "run", str(profile), "--seconds", "1", "--no-reload"],
                          cwd=ROOT, env=env(), capture_output=True, text=True, timeout=30)  # liveness: 1 + 5 s
    assert show.returncode == 1, show.stderr
    assert show.stderr.strip().splitlines()[-1].startswith(f"backend 'osc-in': no frame in 6 s (the time limit, "
                                                           f"1 s, plus 5 s of grace); input: osc osceleton :{port},")
