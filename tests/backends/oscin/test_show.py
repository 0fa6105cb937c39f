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
    assert "disabled" not in err and "Traceback" not in err  # every effect ran on osc-in's frames
    m = json.loads(metrics.read_text())
    assert m["backend"] == "osc-in" and m["frames"] > 20 and m["gestures_by_name"].get("swipe_right") == 1
    assert snapshot.stat().st_size > 0
