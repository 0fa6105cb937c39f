"""Registers the built-in effects, exactly as a third-party plugin would."""
from effects.console import ConsoleEffect
from host import hookimpl


@hookimpl
def register_effects(register):
    register(ConsoleEffect)
