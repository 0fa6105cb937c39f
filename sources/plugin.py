"""Registers the built-in sources, exactly as a third-party plugin would."""
from host import hookimpl
from sources.clip import ClipSource


@hookimpl
def register_sources(register):
    register(ClipSource)
