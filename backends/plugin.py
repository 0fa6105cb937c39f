"""Registers the built-in backends, exactly as a third-party plugin would."""
from backends.engine.backend import (OpenISSBackend, OpenISSNiteBackend, OpenISSNuitrackBackend,
                                     SimpleOpenNIBackend)
from backends.network.backend import NetworkBackend
from backends.replay import ReplayBackend
from backends.truth import TruthBackend
from host import hookimpl


@hookimpl
def register_backends(register):
    register(TruthBackend)
    register(OpenISSBackend)
    register(SimpleOpenNIBackend)
    register(OpenISSNiteBackend)
    register(OpenISSNuitrackBackend)
    register(ReplayBackend)
    register(NetworkBackend)
