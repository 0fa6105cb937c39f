"""Registers the built-in backends, exactly as a third-party plugin would."""
from backends.truth import TruthBackend
from host import hookimpl


@hookimpl
def register_backends(register):
    register(TruthBackend)
