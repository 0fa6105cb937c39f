"""A plugin from its own installed package is discovered, listed and run (NFR3)."""
import json
import subprocess
import sys
import venv
from pathlib import Path

import pytest

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "issv-gesture-log"


@pytest.fixture(scope="module")
def env_python(tmp_path_factory) -> Path:
    """A fresh virtual environment that sees issv but has its own site-packages for the plugin."""
    root = tmp_path_factory.mktemp("venv")
    venv.create(root, system_site_packages=True, with_pip=True)
    python = root / "bin" / "python"
    subprocess.run([python, "-m", "pip", "install", "-q", "--no-deps", "--no-build-isolation", str(EXAMPLE)],
                   check=True, capture_output=True)
    return python


def test_the_installed_plugin_is_listed(env_python):
    out = subprocess.run([env_python, "-m", "host", "list", "--json"], check=True, capture_output=True, text=True)
    effects = {e["name"]: e for e in json.loads(out.stdout)["effects"]}
    assert effects["gesture-log"] == {"name": "gesture-log", "available": True, "reason": None, "plugin": "gesture-log"}
    # ...and only there: this interpreter has not got it
    here = subprocess.run([sys.executable, "-m", "host", "list", "--json"], check=True, capture_output=True, text=True)
    assert "gesture-log" not in {e["name"] for e in json.loads(here.stdout)["effects"]}


def test_the_installed_plugin_runs_in_a_show(env_python, tmp_path):
    profile = tmp_path / "show.toml"
    profile.write_text('backend = "truth"\n[source]\nname = "synthetic"\nseed = 1\n'
                       'choreography = [{action = "idle", duration = 0.5}, {action = "wave", duration = 2.0},\n'
                       '                {action = "idle", duration = 0.5}]\n'
                       '[[effects]]\nname = "gesture-log"\npath = "log.txt"\n[output]\nmode = "headless"\n')
    run = subprocess.run([env_python, "-m", "host", "run", str(profile), "--fast"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    lines = (tmp_path / "log.txt").read_text().splitlines()
    assert [line.split()[1] for line in lines] == ["wave"]
    # the plugin's own subcommand (register_commands) reads what its effect wrote
    count = subprocess.run([env_python, "-m", "host", "gesture-log", str(tmp_path / "log.txt")],
                           capture_output=True, text=True)
    assert count.returncode == 0, count.stderr
    assert count.stdout == "wave 1\n"


def test_a_broken_plugin_is_named_and_skipped_unless_strict(tmp_path):
    dist = tmp_path / "broken_plugin-1.0.dist-info"
    dist.mkdir()
    (dist / "METADATA").write_text("Metadata-Version: 2.1\nName: broken-plugin\nVersion: 1.0\n")
    (dist / "entry_points.txt").write_text("[issv]\nbroken = broken_plugin_module_that_does_not_exist\n")
    env = {"PYTHONPATH": str(tmp_path), "PATH": "/usr/bin:/bin"}
    run = subprocess.run([sys.executable, "-m", "host", "list", "--json"], capture_output=True, text=True, env=env)
    assert run.returncode == 0
    assert "plugin 'broken' from distribution 'broken-plugin' failed to load: ModuleNotFoundError" in run.stderr
    assert "console" in run.stdout  # the built-ins still load
    strict = subprocess.run([sys.executable, "-m", "host", "list", "--json"], capture_output=True, text=True,
                            env={**env, "ISSV_STRICT_PLUGINS": "1"})
    assert strict.returncode != 0 and "broken" in strict.stderr
