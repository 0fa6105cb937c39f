"""The `fake_sdks` fixture: the FAKE middleware packages of fakes/ first on sys.path, then gone.

No NiTE2, Nuitrack or depth sensor can exist on the test machines (see fakes/README.md). The
real `openni` package stays installed; the fixture hides it for one test and restores it.
"""
from __future__ import annotations

import sys
from pathlib import Path

import pytest

FAKES = Path(__file__).parent / "fakes"
PACKAGES = ("openni", "PyNuitrack")


def _ours(name: str) -> bool:
    return any(name == p or name.startswith(p + ".") for p in PACKAGES)


@pytest.fixture
def fake_sdks(monkeypatch):
    """Import `openni` and `PyNuitrack` from the fakes for the duration of one test."""
    for name in [n for n in sys.modules if _ours(n)]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.syspath_prepend(str(FAKES))
    yield FAKES
    for name in [n for n in sys.modules if _ours(n)]:
        del sys.modules[name]  # the fakes' modules; monkeypatch then restores the real ones


@pytest.fixture
def no_sdks(monkeypatch):
    """Neither middleware importable (as on a machine without them), whatever is installed."""
    for name in [n for n in sys.modules if _ours(n)]:
        monkeypatch.delitem(sys.modules, name)
    for package in PACKAGES:
        monkeypatch.setitem(sys.modules, package, None)  # `import openni` raises ImportError


@pytest.fixture(autouse=True)
def fresh_announcements(monkeypatch):
    """Each test sees the once-per-process announcement afresh."""
    from backends.engine import backend

    monkeypatch.setattr(backend, "_announced", set())

