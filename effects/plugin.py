"""Registers the built-in effects, exactly as a third-party plugin would."""
from effects.audio import Audio
from effects.console import ConsoleEffect
from effects.depth_view import DepthView
from effects.digieviss import DigiEVISS
from effects.gesture_burst import GestureBurst
from effects.hand_trails import HandTrails
from effects.isf import Isf
from effects.osc import OscEffect
from effects.osc import command as osc_schema
from effects.silhouette import Silhouette
from effects.star_trail import StarTrail
from host import hookimpl


@hookimpl
def register_effects(register):
    register(ConsoleEffect)
    register(Audio)
    register(OscEffect)
    for effect in (DepthView, HandTrails, StarTrail, GestureBurst, Silhouette, Isf):
        register(effect)
    register(DigiEVISS)


@hookimpl
def register_commands(register):
    register(osc_schema)  # issv osc-schema: the OSC address schemes
    from effects.isf import command
    register(command)
