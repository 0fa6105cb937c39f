"""The generated docs: the profile reference covers every key of every installed plugin, and the
tutorial's effect package passes its own tests."""
import importlib.util
import re
import subprocess
import sys
from pathlib import Path

from host.plugins import KINDS, default_registry
from host.profile import Output

DOCS = Path(__file__).resolve().parents[2] / "docs"


def load_build():
    spec = importlib.util.spec_from_file_location("docs_build", DOCS / "build.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_reference_names_every_plugin_and_every_option():
    text = load_build().reference()
    for kind in KINDS:
        for entry in default_registry().all(kind):
            section = text.split(f"### `{entry.name}`\n", 1)[1].split("\n### ", 1)[0]
            for key in entry.cls.Options.model_fields:
                assert f"| `{key}` |" in section, (entry.name, key)
    for key in Output.model_fields:
        assert f"| `{key}` |" in text
    assert "| `opacity` | number | `1.0` | the layer's opacity (>= 0, <= 1) |" in text


def test_the_committed_reference_is_the_generated_one():
    """Options change with the code: the reference in the repo must be rebuilt with them."""
    def portable(text: str) -> str:  # what this machine lacks is not part of the reference
        return re.sub(r" Not available here: [^\n]*", "", text)

    committed = (DOCS / "profile-reference.md").read_text(encoding="utf-8")
    assert portable(committed) == portable(load_build().reference()), \
        "docs/profile-reference.md is stale: run python3 docs/build.py --reference"


def test_the_tutorial_effect_passes_its_own_tests():
    package = DOCS / "tutorial" / "issv-hand-glow"
    run = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider"], cwd=package,
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr
