"""Registers the built-in sources, exactly as a third-party plugin would."""
from host import hookimpl
from sources.clip import ClipSource
from sources.fakenect import FakenectSource
from sources.oni import OniSource
from sources.recording import RecordingSource
from sources.synthetic import SyntheticSource
from sources.webcam import WebcamSource


@hookimpl
def register_sources(register):
    register(ClipSource)
    register(FakenectSource)
    register(OniSource)
    register(RecordingSource)
    register(SyntheticSource)
    register(WebcamSource)
