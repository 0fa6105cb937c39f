"""The plugin manager: the registry's refusals, check_pending, and the guarded lifecycle hooks."""
from __future__ import annotations

import inspect
import re
import textwrap
from pathlib import Path

import pluggy
import pytest

from host import Backend, Effect, Source, Stage, hookimpl, hookspecs
from host.loop import EffectSlot, Show
from host.plugins import LIFECYCLE_HOOKS, Lifecycle, PluginError, Registry, make_manager
from tests.host.test_loop import BurstBackend, Recorder

ROOT = Path(__file__).resolve().parents[2]


class Hello(Effect):
    name = "hello"


class OtherHello(Effect):
    name = "hello"


class Nameless(Effect):
    pass


class Command:
    NAME = "hello"
    HELP = "says hello"

    @staticmethod
    def add_arguments(parser):
        pass

    @staticmethod
    def main(args):
        return 0


def test_the_registry_refuses_a_duplicate_name_naming_both_plugins():
    registry = Registry()
    registry.register("effects", Hello, "first")
    with pytest.raises(PluginError, match="plugin 'second' registers effect 'hello', already registered by plugin "
                                          "'first'; rename one of them"):
        registry.register("effects", OtherHello, "second")
    assert registry.get("effects", "hello").cls is Hello


def test_the_registry_refuses_the_wrong_kind_of_class_and_a_missing_name():
    registry = Registry()
    with pytest.raises(PluginError, match=r"plugin 'p' registered .*Hello.* as one of its backends, "
                                          r"but it is not a subclass of host.Backend"):
        registry.register("backends", Hello, "p")
    with pytest.raises(PluginError, match="not a subclass of host.Source"):
        registry.register("sources", "clip", "p")  # not even a class
    with pytest.raises(PluginError, match="Nameless has no `name`"):
        registry.register("effects", Nameless, "p")
    assert registry.names("backends") == registry.names("sources") == registry.names("effects") == []
    assert issubclass(BurstBackend, Backend) and not issubclass(Hello, Source)


def test_the_registry_refuses_a_duplicate_command_and_one_without_main():
    registry = Registry()
    registry.register_command(Command, "first")
    with pytest.raises(PluginError, match="plugin 'second' registers command 'hello', already registered by plugin "
                                          "'first'"):
        registry.register_command(Command, "second")

    class Incomplete:
        HELP = "no main"

    with pytest.raises(PluginError, match="without add_arguments, main"):
        registry.register_command(Incomplete, "third")
    assert list(registry.commands) == ["hello"]


def fake_distribution(folder: Path, module: str, source: str) -> None:
    """An installed distribution with one `issv` entry point, as pip would leave it on sys.path."""
    (folder / f"{module}.py").write_text(textwrap.dedent(source))
    dist = folder / f"{module}-1.0.dist-info"
    dist.mkdir()
    (dist / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {module}\nVersion: 1.0\n")
    (dist / "entry_points.txt").write_text(f"[issv]\n{module} = {module}\n")


MISSPELLED = """
    from host import hookimpl

    @hookimpl
    def register_efects(register):  # one letter short: never called
        pass
"""


def test_check_pending_reports_a_misspelled_hook_and_strict_mode_refuses_it(tmp_path, monkeypatch, capsys):
    fake_distribution(tmp_path, "typo_plugin", MISSPELLED)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delenv("ISSV_STRICT_PLUGINS", raising=False)
    make_manager()
    err = capsys.readouterr().err
    assert "plugin 'typo_plugin' implements a hook issv does not have" in err and "register_efects" in err
    monkeypatch.setenv("ISSV_STRICT_PLUGINS", "1")
    with pytest.raises(PluginError, match="register_efects"):
        make_manager()


class Listener:
    """An in-process plugin that records what the lifecycle hooks told it."""

    def __init__(self):
        self.calls = []

    @hookimpl
    def host_started(self, show):
        self.calls.append(("host_started", show.metrics.frames))

    @hookimpl
    def host_stopping(self, show):
        self.calls.append(("host_stopping", show.metrics.frames))

    @hookimpl
    def effect_failed(self, effect, error, phase):
        self.calls.append(("effect_failed", effect.name, str(error), phase))


class Raising:
    @hookimpl
    def host_started(self, show):
        raise RuntimeError("cannot start")

    @hookimpl
    def effect_failed(self, effect, error, phase):
        raise KeyError("no such effect")


def manager(*plugins: tuple[str, object]) -> pluggy.PluginManager:
    pm = pluggy.PluginManager("issv")
    pm.add_hookspecs(hookspecs)
    for name, plugin in plugins:
        pm.register(plugin, name=name)
    pm.check_pending()
    return pm


def show_with(pm: pluggy.PluginManager, effects: list[Effect], frames: int = 20) -> Show:
    slots = [EffectSlot(e, f"effects[{i}]") for i, e in enumerate(effects)]
    show = Show(BurstBackend(frames), slots, Stage((64, 48), 500.0, "burst"), pm=pm)
    show.run()
    return show


def test_lifecycle_hooks_are_called_once_each_with_the_show():
    listener = Listener()
    broken = Recorder(fail_on_frame=3)
    show = show_with(manager(("listener", listener)), [broken, Recorder()])
    names = [c[0] for c in listener.calls]
    assert names == ["host_started", "effect_failed", "host_stopping"]
    assert listener.calls[0][1] == 0  # before the first frame
    assert listener.calls[1][1:] == ("recorder", "boom", "on_frame")
    assert listener.calls[2][1] == show.metrics.frames == 20  # the final figures


def test_a_raising_hook_implementation_is_named_skipped_and_the_show_goes_on(capsys):
    listener, healthy = Listener(), Recorder()
    show = show_with(manager(("listener", listener), ("raising", Raising())),
                     [Recorder(fail_on_frame=1), Recorder(fail_on_frame=2), healthy])
    err = capsys.readouterr().err
    assert "plugin 'raising' raised RuntimeError in host_started: cannot start; that hook of the plugin is skipped" in err
    assert err.count("plugin 'raising' raised KeyError in effect_failed") == 1  # once, then skipped
    assert [c[0] for c in listener.calls].count("effect_failed") == 2  # the other plugin heard both
    assert listener.calls[-1] == ("host_stopping", 20)
    assert show.metrics.frames == 20 and healthy.events == [(i, k) for i in range(1, 21) for k in range(2)]


def test_only_lifecycle_hooks_go_through_the_guard():
    with pytest.raises(ValueError, match="not a lifecycle hook"):
        Lifecycle(manager())("register_effects", register=print)


def test_every_hook_is_typed_and_documented_with_its_exact_signature():
    """datasette's habit: the plugin docs show every hook exactly as hookspecs.py declares it."""
    docs = (ROOT / "README.md").read_text(encoding="utf-8")
    for name, spec in inspect.getmembers(hookspecs, inspect.isfunction):
        if not hasattr(spec, "issv_spec"):
            continue
        signature = inspect.signature(spec)
        assert all(p.annotation is not inspect.Parameter.empty for p in signature.parameters.values()), name
        shown = re.sub(r"'|\"", "", f"{name}{signature}")
        assert shown in re.sub(r"'|\"", "", docs), f"README.md does not document `{shown}`"
    assert set(LIFECYCLE_HOOKS) <= {n for n, f in inspect.getmembers(hookspecs, inspect.isfunction)
                                    if hasattr(f, "issv_spec")}
