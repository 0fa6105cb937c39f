"""`issv new-effect`: the scaffolded package passes its own test, installs, is listed and runs."""
import json
import subprocess
import sys
import venv

import pytest

from host.errors import UserError
from host.scaffold import scaffold


def run(*cmd, **kw):
    return subprocess.run([str(c) for c in cmd], capture_output=True, text=True, **kw)


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """`issv new-effect hand-glow`, then pip install into a fresh venv that sees issv."""
    work = tmp_path_factory.mktemp("scaffold")
    made = run(sys.executable, "-m", "host", "new-effect", "hand-glow", "-o", work)
    assert made.returncode == 0, made.stderr
    root = work / "issv-hand-glow"
    env_dir = work / "venv"
    venv.create(env_dir, system_site_packages=True, with_pip=False)  # this pip installs into it
    python = env_dir / "bin" / "python"
    pip = run(sys.executable, "-m", "pip", "--python", python, "install", "-q", "--no-deps",
              "--no-build-isolation", root)
    assert pip.returncode == 0, pip.stderr
    return python, root


def test_the_package_has_what_an_installable_effect_needs(installed):
    _, root = installed
    files = sorted(str(p.relative_to(root)) for p in root.rglob("*") if p.is_file() and "build" not in p.parts
                   and ".egg-info" not in str(p))
    assert files == ["README.md", "issv_hand_glow/__init__.py", "pyproject.toml", "tests/test_issv_hand_glow.py"]
    assert 'hand-glow = "issv_hand_glow"' in (root / "pyproject.toml").read_text()
    source = (root / "issv_hand_glow" / "__init__.py").read_text()
    imports = [line for line in source.splitlines() if line.startswith(("import ", "from "))]
    assert all(line.split()[1] in ("__future__", "pydantic", "host") for line in imports), imports


def test_its_own_test_passes_out_of_the_box(installed):
    python, root = installed
    result = run(python, "-m", "pytest", "-q", "-p", "no:cacheprovider", cwd=root)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "2 passed" in result.stdout


def test_once_installed_it_is_listed_there_and_only_there(installed):
    python, _ = installed
    listed = json.loads(run(python, "-m", "host", "list", "--json").stdout)
    effects = {e["name"]: e for e in listed["effects"]}
    assert effects["hand-glow"]["available"] and effects["hand-glow"]["plugin"] == "hand-glow"
    here = json.loads(run(sys.executable, "-m", "host", "list", "--json").stdout)
    assert "hand-glow" not in {e["name"] for e in here["effects"]}


def test_it_runs_in_a_profile(installed, tmp_path):
    python, _ = installed
    profile = tmp_path / "show.toml"
    profile.write_text('backend = "truth"\n[source]\nname = "synthetic"\nseed = 1\n'
                       'choreography = [{action = "idle", duration = 0.5}, {action = "wave", duration = 2.0},\n'
                       '                {action = "idle", duration = 0.5}]\n'
                       '[[effects]]\nname = "hand-glow"\ngestures = ["wave"]\n[output]\nmode = "headless"\n')
    result = run(python, "-m", "host", "run", profile, "--fast", "--headless")
    assert result.returncode == 0, result.stderr
    assert "hand-glow: wave by the right hand (1 so far)" in result.stdout


def test_bad_names_and_existing_folders_are_refused(tmp_path):
    with pytest.raises(UserError, match="not a usable effect name"):
        scaffold("Hand Glow", tmp_path)
    scaffold("glow", tmp_path)
    with pytest.raises(UserError, match="already exists"):
        scaffold("glow", tmp_path)
    taken = run(sys.executable, "-m", "host", "new-effect", "console", "-o", tmp_path)
    assert taken.returncode == 1 and "already installed" in taken.stderr
