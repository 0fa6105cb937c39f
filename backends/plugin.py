"""Registers the built-in backends, exactly as a third-party plugin would."""
from backends.engine.backend import OpenISSBackend, SimpleOpenNIBackend
from backends.network import command as serve
from backends.network.backend import NetworkBackend
from backends.oscin.backend import OscInBackend
from backends.replay import ReplayBackend
from backends.sdk.nite import NiteBackend
from backends.sdk.nuitrack import NuitrackBackend
from backends.truth import TruthBackend
from backends.webcam.backend import MediaPipeBackend
from host import hookimpl


@hookimpl
def register_backends(register):
    register(TruthBackend)
    register(OpenISSBackend)
    register(SimpleOpenNIBackend)
    register(NiteBackend)  # openiss-nite: NiTE2 when installed, else the open engine in NiTE mode
    register(NuitrackBackend)  # openiss-nuitrack: Nuitrack when installed, else the engine in its mode
    register(ReplayBackend)
    register(NetworkBackend)
    register(OscInBackend)
    register(MediaPipeBackend)  # needs the `webcam` extra; `issv list` says how to get it


@hookimpl
def register_commands(register):
    register(serve)  # issv serve: publish a profile's frames for the network backend
    from backends.oscin import replay
    register(replay)
