"""Fixtures for the OSC tests: a UDP receiver, Pure Data, oscdump (real processes and sockets)."""
import pytest

from tests.effects.osc.helpers import OscDump, PureData, Receiver


@pytest.fixture
def receiver():
    r = Receiver()
    yield r
    r.close()


@pytest.fixture
def pd():
    echo = Receiver()
    pure_data = PureData(echo)
    yield pure_data
    pure_data.close()
    echo.close()


@pytest.fixture
def oscdump():
    dump = OscDump()
    yield dump
    if dump.proc.poll() is None:
        dump.proc.kill()
        dump.proc.wait()
