"""Writes a new, installable effect package: the quickest way from an idea to an effect on stage.

The package is what a third-party plugin looks like (README.md, "Writing a plugin"): a
pyproject.toml with its `issv` entry point, one module with the effect class and its hookimpl, a
test that passes as written, and a README that says how to install, test and use it.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from string import Template

from host.errors import UserError

NAME = re.compile(r"^[a-z][a-z0-9]*(-[a-z0-9]+)*$")


@dataclass(frozen=True)
class Names:
    """Every spelling of one effect name: `hand-glow` -> issv-hand-glow, issv_hand_glow, HandGlow."""

    name: str

    @property
    def distribution(self) -> str:
        return f"issv-{self.name}"

    @property
    def module(self) -> str:
        return "issv_" + self.name.replace("-", "_")

    @property
    def cls(self) -> str:
        return "".join(part.capitalize() for part in self.name.split("-"))


def check_name(name: str) -> Names:
    if not NAME.match(name):
        raise UserError(f"issv new-effect: {name!r} is not a usable effect name; use lowercase letters, digits "
                        f"and single hyphens, starting with a letter (e.g. hand-glow)")
    return Names(name)


PYPROJECT = Template('''\
[build-system]
requires = ["setuptools>=61"]
build-backend = "setuptools.build_meta"

[project]
name = "$distribution"
version = "0.1.0"
description = "An issv effect: $name."
readme = "README.md"
requires-python = ">=3.11"
dependencies = ["issv"]

# This line is how issv finds the effect once the package is installed.
[project.entry-points.issv]
$name = "$module"

[tool.setuptools]
packages = ["$module"]

[tool.pytest.ini_options]
pythonpath = ["."]
testpaths = ["tests"]
''')

MODULE = Template('''\
"""`$name`: an issv effect. Edit it: every hook is optional, keep the ones you need."""
from __future__ import annotations

from pydantic import BaseModel, ConfigDict

from host import Effect, Frame, Gesture, GestureState, Stage, hookimpl


class ${cls}Options(BaseModel):
    """What a profile may set under [[effects]] name = "$name"; anything else is an error."""

    model_config = ConfigDict(extra="forbid")
    gestures: list[str] = ["wave", "click", "swipe_left", "swipe_right", "swipe_up", "swipe_down", "hand_raise"]


class $cls(Effect):
    name = "$name"
    Options = ${cls}Options

    def setup(self, stage: Stage) -> None:
        """Once, before the show: `stage.size` is the output in pixels, `stage.ctx` the moderngl
        context (None when nothing is drawn)."""
        super().setup(stage)
        self.count = 0
        self.hands: dict[int, tuple[float, float, float]] = {}

    def on_gesture(self, gesture: Gesture) -> None:
        """Every gesture event, exactly once, in order (IN_PROGRESS, then COMPLETE)."""
        if gesture.state is GestureState.COMPLETE and gesture.name in self.options.gestures:
            self.count += 1
            print(f"$name: {gesture.name} by the {gesture.side.value} hand ({self.count} so far)", flush=True)

    def on_frame(self, frame: Frame) -> None:
        """The newest frame: hands in millimetres (x right, y up, z away from the camera)."""
        self.hands = {hand.id: hand.position for hand in frame.hands}

    def close(self) -> None:
        """Once, after the show: release what setup acquired."""


@hookimpl
def register_effects(register):
    register($cls)
''')

TEST = Template('''\
"""Tests for `$name`: run them with `python -m pytest` in this folder."""
from host import Frame, Gesture, GestureState, GestureType, Hand, HandState, Side, Stage

from $module import $cls


def make_effect(**options):
    effect = $cls($cls.Options(**options))
    effect.setup(Stage(size=(640, 480), fps=30.0, backend="test"))
    return effect


def gesture(kind, state=GestureState.COMPLETE):
    return Gesture(kind, state, (100.0, 200.0, 1500.0), hand_id=1, side=Side.RIGHT)


def test_counts_the_completed_gestures_it_listens_for(capsys):
    effect = make_effect(gestures=["wave"])
    effect.on_gesture(gesture(GestureType.WAVE, GestureState.IN_PROGRESS))
    effect.on_gesture(gesture(GestureType.WAVING))  # Nuitrack's wave is a wave too
    effect.on_gesture(gesture(GestureType.CLICK))
    assert effect.count == 1
    assert "$name: wave by the right hand" in capsys.readouterr().out


def test_follows_the_hands():
    effect = make_effect()
    effect.on_frame(Frame(1, 0.0, None, (Hand(7, HandState.TRACKING, (10.0, 20.0, 1500.0)),)))
    assert effect.hands == {7: (10.0, 20.0, 1500.0)}
''')

README = Template('''\
# $distribution

An effect named `$name` for issv (gesture-driven stage visuals).

```
pip install -e .              # install it next to issv
python -m pytest              # its tests
issv list                     # `$name` is listed under effects
```

Use it in a profile:

```toml
[[effects]]
name = "$name"
gestures = ["wave", "click"]
```

The effect is `$module/__init__.py`. Its options are the fields of `${cls}Options`; `issv check`
names any mistake in a profile. The hooks (`setup`, `on_gesture`, `on_frame`, `render`, `close`)
are described in issv's `docs/tutorial.md`.
''')


def scaffold(name: str, out_dir: Path) -> Path:
    """Write the package for effect `name` into out_dir/issv-NAME; returns that folder."""
    names = check_name(name)
    root = out_dir / names.distribution
    if root.exists():
        raise UserError(f"issv new-effect: {root} already exists; pick another name or folder (-o DIR)")
    fields = {"name": names.name, "distribution": names.distribution, "module": names.module, "cls": names.cls}
    files = {
        "pyproject.toml": PYPROJECT,
        f"{names.module}/__init__.py": MODULE,
        f"tests/test_{names.module}.py": TEST,
        "README.md": README,
    }
    try:
        for relative, template in files.items():
            path = root / relative
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(template.substitute(fields), encoding="utf-8")
    except OSError as error:
        raise UserError(f"issv new-effect: cannot write {root}: {error}") from None
    return root
