"""Without a usable middleware both adapters run the open engine in that middleware's mode, say why once."""
from __future__ import annotations

import pytest

from backends.engine.backend import Engine
from backends.engine.recognizer import NITE_DICTIONARY, NUITRACK_DICTIONARY
from backends.sdk.nite import NiteBackend
from backends.sdk.nuitrack import NuitrackBackend
from host.plugins import default_registry
from tests.backends.sdk.sources import Camera, Recording


def play(backend):
    with backend:
        assert not backend.runs_sdk
        frames = [f for f in iter(backend.update, None)]
        assert isinstance(backend.engine, Engine) and backend.engine.last is not None  # the open engine ran
        return frames


@pytest.mark.parametrize("cls, says", [
    (NiteBackend, "the PyPI package `openni` (OpenNI2/NiTE2 bindings) is missing: pip install openni"),
    (NuitrackBackend, "Nuitrack runtime not found (its Python bindings PyNuitrack are missing"),
])
def test_without_the_runtime_the_engine_runs_and_it_is_said_once(no_sdks, monkeypatch, cls, says, capsys):
    monkeypatch.delenv("NITE2_REDIST", raising=False)
    monkeypatch.delenv("NITE2_REDIST64", raising=False)
    assert not cls.implementation().sdk and says in cls.implementation().why
    camera = Camera()
    frames = play(cls(camera))
    play(cls(Camera()))
    assert len(frames) == len(camera.scene) and all(f.backend == cls.name for f in frames)
    err = capsys.readouterr().err
    assert err.count(f"issv: {cls.name}:") == 1 and says in err and "running the open engine in" in err


def test_the_real_openni_package_without_nite2_falls_back(monkeypatch, capsys):
    pytest.importorskip("openni.nite2")  # the real PyPI bindings (installed with the project)
    monkeypatch.delenv("NITE2_REDIST", raising=False)
    monkeypatch.delenv("NITE2_REDIST64", raising=False)
    play(NiteBackend(Camera(), NiteBackend.Options(device="any")))
    assert "NiTE2 runtime not found" in capsys.readouterr().err


@pytest.mark.parametrize("content, options, source, says", [
    (b"not a library", {"device": "any"}, Camera(), "cannot be loaded"),
    (None, {"device": "any"}, Camera(), "no OpenNI2 device 'any' for NiTE2"),
    (None, {}, Recording(), "source 'clip' is not one (use source 'oni'"),
])
def test_nite2_failures_name_the_cause_and_run_the_engine(fake_sdks, tmp_path, content, options, source, says, capsys):
    from openni import nite2, openni2

    (tmp_path / "libNiTE2.so").write_bytes(content or nite2.FAKE_RUNTIME)
    openni2.fake_devices.clear()
    frames = play(NiteBackend(source, NiteBackend.Options(nite2_redist=str(tmp_path), **options)))
    assert len(frames) == len(source.scene)
    err = capsys.readouterr().err
    assert says in err and "running the open engine in NiTE mode" in err


def test_the_registered_backends_are_the_sdk_capable_ones_and_always_available():
    registry = default_registry()
    for cls, dictionary in ((NiteBackend, NITE_DICTIONARY), (NuitrackBackend, NUITRACK_DICTIONARY)):
        entry = registry.get("backends", cls.name)
        assert entry.cls is cls and entry.availability() is None
        assert cls.dictionary == dictionary
