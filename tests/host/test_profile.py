import subprocess
import sys

import pytest
from pydantic import BaseModel, ConfigDict

from backends.engine.rules import GestureRules
from backends.truth import TruthBackend
from host import Effect
from host.errors import ProfileError
from host.options import Color, ProfilePath
from host.plugins import Registry
from host.profile import parse
from sources.clip import ClipSource


class DotOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    color: Color = (1.0, 1.0, 1.0)
    size: float = 10.0
    image: ProfilePath | None = None


class Dot(Effect):
    name = "dot"
    Options = DotOptions


@pytest.fixture
def registry():
    r = Registry()
    r.register("backends", TruthBackend, "test")
    r.register("sources", ClipSource, "test")
    r.register("effects", Dot, "test")
    return r


def errors(text, registry):
    with pytest.raises(ProfileError) as caught:
        parse(text, "profiles/x.toml", "/show", registry)
    return caught.value.lines


GOOD = 'backend = "truth"\n[source]\nname = "clip"\npath = "c.npz"\n'


def test_a_good_profile_resolves_classes_options_and_relative_paths(registry):
    prof = parse(GOOD + '[[effects]]\nname = "dot"\ncolor = [1, 0.5, 0]\nimage = "img/a.png"\n',
                 "profiles/x.toml", "/show", registry)
    assert prof.backend.cls is TruthBackend
    assert prof.source.options.path == "/show/c.npz"
    assert prof.effects[0].options.color == (1.0, 0.5, 0.0)
    assert prof.effects[0].options.image == "/show/img/a.png"


def test_wrong_colour_names_file_key_path_expected_and_found(registry):
    text = GOOD + '[[effects]]\nname = "dot"\n[[effects]]\nname = "dot"\ncolor = "red"\n'
    assert errors(text, registry) == ['profiles/x.toml: effects[1].color: expected 3 numbers from 0 to 1, got "red"']


def test_every_problem_is_reported_once(registry):
    text = ('backend = "nope"\n[source]\nname = "clip"\n'
            '[[effects]]\nname = "dot"\nsize = "big"\nsparkle = 1\n')
    lines = errors(text, registry)
    assert lines[0] == ('profiles/x.toml: backend.name: expected one of truth, got "nope" '
                        '(`issv list` shows what is installed)')
    assert any(l.startswith("profiles/x.toml: source.path: required key is missing") for l in lines)
    assert any("effects[0].size: expected a valid number" in l and 'got "big"' in l for l in lines)
    assert any(l.startswith("profiles/x.toml: effects[0].sparkle: unknown key; expected one of: color, image, size")
               for l in lines)
    assert len(lines) == 4


def test_an_unknown_key_in_a_nested_table_names_the_keys_of_that_table():
    """`[backend] gestures = {...}` holds the recogniser's 70-odd thresholds, not the backend's keys."""
    with pytest.raises(ProfileError) as caught:
        parse('[source]\nname = "synthetic"\n[backend]\nname = "openiss"\n'
              'gestures = { raise_stil_s = 0.1 }\nsmoothing = { beta_ = 0.1 }\n', "profiles/x.toml", "/show")
    gestures, smoothing = sorted(caught.value.lines)
    assert gestures.startswith("profiles/x.toml: backend.gestures.raise_stil_s: unknown key; did you mean "
                               "raise_still_s, ")  # the nearest first
    keys = len(GestureRules.model_fields)
    assert gestures.endswith(f"? ({keys} keys here: docs/profile-reference.md lists them)")
    assert smoothing == ("profiles/x.toml: backend.smoothing.beta_: unknown key; "
                         "expected one of: beta, d_cutoff_hz, enabled, min_cutoff_hz")


def test_broken_toml_and_top_level_keys(registry):
    assert errors("backend = \n", registry)[0].startswith("profiles/x.toml: not valid TOML")
    assert errors(GOOD + "[output]\nfps = -3\n", registry) == [
        "profiles/x.toml: output.fps: expected greater than 0, got -3"]


def test_issv_check_exits_2_with_one_line_and_no_traceback(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('backend = "truth"\n[source]\nname = "clip"\npath = "x.npz"\nloop = "often"\n')
    run = subprocess.run([sys.executable, "-m", "host", "check", str(bad)], capture_output=True, text=True)
    assert run.returncode == 2
    assert run.stderr.strip() == f"{bad}: source.loop: expected a valid boolean, unable to interpret input, got \"often\""
    assert "Traceback" not in run.stderr


def test_shipped_profiles_are_valid():
    from pathlib import Path
    profiles = sorted(str(p) for p in Path(__file__).resolve().parents[2].glob("profiles/*.toml"))
    assert profiles
    run = subprocess.run([sys.executable, "-m", "host", "check", *profiles], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr


class ColourSource(ClipSource):
    """A source of colour frames (as a webcam gives), for the fit check."""

    name = "colour"
    frames = "colour"


class ColourBackend(TruthBackend):
    name = "colour-tracker"
    takes = "colour"


def test_a_backend_and_a_source_of_different_frames_do_not_fit(registry):
    registry.register("sources", ColourSource, "test")
    registry.register("backends", ColourBackend, "test")
    assert errors(GOOD.replace('"clip"', '"colour"'), registry) == [
        "profiles/x.toml: [backend] 'truth' tracks depth frames, but [source] 'colour' gives colour frames: "
        "pick a source with depth frames or a backend that takes colour ones (`issv list` says which is which)"]
    assert "[backend] 'colour-tracker' tracks colour frames, but [source] 'clip' gives depth frames" in \
        errors(GOOD.replace('"truth"', '"colour-tracker"'), registry)[0]
    parse(GOOD.replace('"clip"', '"colour"').replace('"truth"', '"colour-tracker"'), "x.toml", "/show", registry)


def test_a_source_the_backend_does_not_use_is_a_warning():
    from backends.oscin.backend import OscInBackend
    r = Registry()
    r.register("backends", OscInBackend, "test")
    r.register("sources", ClipSource, "test")
    prof = parse('backend = "osc-in"\n[source]\nname = "clip"\npath = "c.npz"\n', "p.toml", "/show", r)
    assert prof.source is None
    assert prof.warnings == ["p.toml: [source] 'clip' is not used: backend 'osc-in' makes its own frames "
                             "(it takes no source)"]


def test_an_unavailable_effect_is_a_warning_and_skipped(registry):
    class Missing(Dot):
        name = "missing"

        @classmethod
        def availability(cls):
            return "needs pip install 'issv[x]'"
    registry.register("effects", Missing, "test")
    prof = parse('backend = "truth"\n[source]\nname = "clip"\npath = "c.npz"\n[[effects]]\nname = "missing"\n'
                 '[[effects]]\nname = "dot"\n', "p.toml", "/show", registry)
    assert [r.ref.name for r in prof.effects] == ["dot"]
    assert prof.warnings == ["p.toml: effects[0]: effect 'missing' is not available here: needs pip install "
                             "'issv[x]'; that effect is skipped"]
