"""Live reload: edits to the running profile and to an effect's source reach a real `issv run`
without stopping it; a broken edit keeps the previous version running and says why in one line."""
import os
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import pytest

from tests.conftest import write_clip

PROBE = '''
from pathlib import Path
from pydantic import BaseModel, ConfigDict
from host import Effect, hookimpl

VERSION = "{version}"


class ProbeOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    label: str = "a"
    out: str


class Probe(Effect):
    """Writes which code and which options are running, every frame."""
    name = "probe"
    Options = ProbeOptions

    def on_frame(self, frame):
        Path(self.options.out).write_text(f"{{VERSION}} {{self.options.label}} {{frame.seq}}")


@hookimpl
def register_effects(register):
    register(Probe)
'''


def write_plugin(root: Path, version: str) -> Path:
    module = root / "reload_probe.py"
    module.write_text(PROBE.format(version=version))
    dist = root / "reload_probe-1.0.dist-info"
    dist.mkdir(exist_ok=True)
    (dist / "METADATA").write_text("Metadata-Version: 2.1\nName: reload-probe\nVersion: 1.0\n")
    (dist / "entry_points.txt").write_text("[issv]\nprobe = reload_probe\n")
    return module


def write_profile(path: Path, clip: Path, out: Path, label: str) -> None:
    path.write_text(f'backend = "truth"\n[source]\nname = "clip"\npath = "{clip}"\nloop = true\n'
                    f'[[effects]]\nname = "probe"\nout = "{out}"\nlabel = {label}\n'
                    f'[output]\nmode = "headless"\nhud = false\n')


def wait_for(out: Path, prefix: str, timeout: float = 10.0) -> tuple[float, int]:
    """Seconds until the running show reports `prefix`, and the frame it said it then."""
    start = time.monotonic()
    while time.monotonic() - start < timeout:
        try:
            text = out.read_text()
        except FileNotFoundError:
            text = ""
        if text.startswith(prefix + " "):
            return time.monotonic() - start, int(text.split()[-1])
        time.sleep(0.02)
    raise AssertionError(f"the show never reported {prefix!r}; last: {text!r}")


def test_profile_and_source_edits_reach_the_running_show(tmp_path):
    clip = write_clip(tmp_path / "clip.npz", frames=30)
    module = write_plugin(tmp_path, "v1")
    out, profile, log = tmp_path / "probe.txt", tmp_path / "show.toml", tmp_path / "stderr.txt"
    write_profile(profile, clip, out, '"a"')
    env = {**os.environ, "PYTHONPATH": str(tmp_path)}
    with log.open("w") as err:
        show = subprocess.Popen([sys.executable, "-m", "host", "run", str(profile), "--headless"],
                                stdout=subprocess.DEVNULL, stderr=err, env=env)
    try:
        _, first = wait_for(out, "v1 a", timeout=30.0)

        write_profile(profile, clip, out, '"b"')  # the profile
        _, frame = wait_for(out, "v1 b")
        assert frame > first  # the same show, still going

        module.write_text(PROBE.format(version="v2"))  # the effect's source
        _, frame = wait_for(out, "v2 b")

        module.write_text(PROBE.format(version="v3").replace("class Probe(Effect):", "class Probe(Effect"))
        write_profile(profile, clip, out, "5")  # then a bad value in the profile
        time.sleep(1.5)
        _, later = wait_for(out, "v2 b")
        assert later > frame  # the previous version kept running
        errors = [line for line in log.read_text().splitlines() if "reload failed" in line]
        assert any("reload_probe: SyntaxError" in line and "line" in line for line in errors), errors

        write_profile(profile, clip, out, '"c"')  # fixing the profile alone is not enough...
        module.write_text(PROBE.format(version="v3"))  # ...until the source is fixed too
        wait_for(out, "v3 c")
        assert show.poll() is None
    finally:
        show.send_signal(signal.SIGINT)
        code = show.wait(timeout=20)
    assert code == 0, log.read_text()
    text = log.read_text()
    assert "issv: reloaded reload_probe: 1 effect(s) rebuilt, 0 kept" in text
    assert all(len(line) < 300 for line in text.splitlines() if "reload" in line)


def test_no_reload_flag_ignores_edits(tmp_path):
    clip = write_clip(tmp_path / "clip.npz", frames=30)
    write_plugin(tmp_path, "v1")
    out, profile = tmp_path / "probe.txt", tmp_path / "show.toml"
    write_profile(profile, clip, out, '"a"')
    env = {**os.environ, "PYTHONPATH": str(tmp_path)}
    show = subprocess.Popen([sys.executable, "-m", "host", "run", str(profile), "--headless", "--no-reload"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env, text=True)
    try:
        wait_for(out, "v1 a", timeout=30.0)
        write_profile(profile, clip, out, '"b"')
        time.sleep(1.5)
        wait_for(out, "v1 a")
    finally:
        show.send_signal(signal.SIGINT)
        show.wait(timeout=20)


@dataclass
class InProcess:
    """A show run in this process with an effect package `probe_pkg` (effect.py reading WORD from
    words.py) and its reloader checking at every call."""

    path: Path  # the profile
    words: Path
    show: object
    reloader: object
    said: list[str]


PROBE_ONLY = 'backend = "idle"\n[[effects]]\nname = "probe"\n'
PROBE_AND_CONSOLE = PROBE_ONLY + '[[effects]]\nname = "console"\n'


@pytest.fixture
def in_process(tmp_path, monkeypatch):
    from effects.console import ConsoleEffect
    from host import Backend, Stage
    from host.assemble import make_effects
    from host.loop import Show
    from host.plugins import Registry
    from host.profile import load
    from host.reload import Reloader

    class Idle(Backend):
        name = "idle"
        needs_source = False

    pkg = tmp_path / "probe_pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("from probe_pkg.effect import Probe\n")
    (pkg / "effect.py").write_text("from host import Effect\nfrom probe_pkg.words import WORD\n\n\n"
                                   "class Probe(Effect):\n    name = 'probe'\n\n"
                                   "    def setup(self, stage):\n        self.word = WORD\n")
    words = pkg / "words.py"
    words.write_text('WORD = "one"\n')
    monkeypatch.syspath_prepend(str(tmp_path))
    import probe_pkg
    try:
        registry = Registry()
        for kind, cls in (("effects", probe_pkg.Probe), ("effects", ConsoleEffect), ("backends", Idle)):
            registry.register(kind, cls, "test")
        path = tmp_path / "show.toml"
        path.write_text(PROBE_ONLY)
        profile = load(path, registry)
        show = Show(Idle(), make_effects(profile), Stage((64, 48), 30.0, "idle"))
        show.effects[0].effect.setup(show.stage)
        said = []
        yield InProcess(path, words, show, Reloader(profile, registry, interval=0.0, say=said.append), said)
    finally:
        for name in [n for n in sys.modules if n.startswith("probe_pkg")]:
            del sys.modules[name]


def test_an_effect_package_reloads_whole_and_unchanged_effects_keep_their_state(in_process):
    """In-process: editing a submodule of an effect's package rebuilds the effect; a broken edit
    restores every module as it was; a profile edit elsewhere keeps the running instance."""
    run, show, words, said = in_process, in_process.show, in_process.words, in_process.said
    words.write_text('WORD = "two!"\n')
    run.reloader(show)
    assert show.effects[0].effect.word == "two!", said
    assert run.reloader.registry.get("effects", "probe").cls is sys.modules["probe_pkg.effect"].Probe

    words.write_text("WORD = (\n")
    run.reloader(show)
    assert show.effects[0].effect.word == "two!"
    assert sys.modules["probe_pkg.words"].WORD == "two!"  # put back as it was
    assert "SyntaxError" in said[-1] and "words.py" in said[-1] and "\n" not in said[-1]

    running = show.effects[0].effect
    run.path.write_text(PROBE_AND_CONSOLE)
    run.reloader(show)
    assert show.effects[0].effect is running and [s.effect.name for s in show.effects] == ["probe", "console"]
    assert said[-1] == "issv: reloaded show.toml: 1 effect(s) rebuilt, 1 kept"


def test_an_effect_put_back_in_the_profile_runs_its_source_as_edited_meanwhile(in_process):
    """CI caught it: the profile, read as it was being saved, had no effects for a moment, so the
    effect's source left the watch; edited then, the edit was taken as already loaded and the
    show kept the old code for good."""
    run, show = in_process, in_process.show
    run.path.write_text('backend = "idle"\n[[effects]]\nname = "console"\n')  # the probe taken out
    run.reloader(show)
    run.words.write_text('WORD = "edited while out"\n')
    run.reloader(show)
    run.path.write_text(PROBE_ONLY)  # put back: the old code first, then the edit
    run.reloader(show)
    run.reloader(show)
    assert [s.effect.name for s in show.effects] == ["probe"]
    assert show.effects[0].effect.word == "edited while out", run.said


def test_a_profile_emptied_as_an_editor_saves_it_is_not_loaded(in_process):
    """Saving truncates the file before writing it: an empty profile is no show (it would take every
    effect off stage); the saved one is loaded at the next check."""
    run, show = in_process, in_process.show
    running = show.effects[0].effect
    run.path.write_text("")
    run.reloader(show)
    assert show.effects[0].effect is running and run.said == []
    run.path.write_text(PROBE_AND_CONSOLE)
    run.reloader(show)
    assert [s.effect.name for s in show.effects] == ["probe", "console"]
