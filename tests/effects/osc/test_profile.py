"""profiles/osc.toml: the default scheme to 127.0.0.1:9000 from the synthetic performer."""
from host import Stage
from host.assemble import make_backend, make_effects
from host.loop import Limits, Show
from host.plugins import default_registry
from host.profile import load, parse
from tests.effects.osc.helpers import ROOT

PROFILE = ROOT / "profiles" / "osc.toml"


def osc_profile():
    """The profile as shipped; on `truth` until the open engine (`openiss`) is registered."""
    if default_registry().get("backends", "openiss") is not None:
        return load(PROFILE)
    text = PROFILE.read_text().replace('name = "openiss"', 'name = "truth"')
    return parse(text, str(PROFILE), PROFILE.parent)


def test_the_profile_sends_the_default_scheme_to_port_9000():
    profile = osc_profile()
    assert profile.model.source.name == "synthetic" and profile.model.backend.name in ("openiss", "truth")
    (osc,) = [r for r in profile.effects if r.ref.name == "osc"]
    assert osc.options.destinations == ["127.0.0.1:9000"] and osc.options.scheme == "issv"
    assert osc.options.prefix is None and osc.options.pd_safe


def test_the_profile_plays_to_a_receiver(oscdump):
    """The same show, sent to oscdump on a free port (9000 may be taken while tests run in parallel)."""
    profile = osc_profile()
    for resolved in profile.effects:
        if resolved.ref.name == "osc":
            resolved.options = resolved.options.model_copy(update={"destinations": [oscdump.address]})
    backend = make_backend(profile, realtime=False)
    show = Show(backend, make_effects(profile), Stage((640, 480), 240.0, backend.name), limits=Limits(frames=90))
    show.run()
    lines = oscdump.stop(until=lambda lines: any(line[1] == "/issv/hand" for line in lines))
    assert {"/issv/frame", "/issv/hand"} <= {line[1] for line in lines}
    assert {line[2] for line in lines if line[1] == "/issv/hand"} == {"issffff"}
