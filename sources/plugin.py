"""Registers the built-in sources, exactly as a third-party plugin would."""
from host import hookimpl
from sources.clip import ClipSource
from sources.depth_images import DepthImagesSource
from sources.fakenect import FakenectSource
from sources.kinect import KinectSource
from sources.oni import OniSource
from sources.realsense import RealSenseSource
from sources.recording import RecordingSource
from sources.synthetic import SyntheticSource
from sources.webcam import WebcamSource


@hookimpl
def register_sources(register):
    register(ClipSource)
    register(DepthImagesSource)
    register(FakenectSource)
    register(KinectSource)
    register(OniSource)
    register(RealSenseSource)
    register(RecordingSource)
    register(SyntheticSource)
    register(WebcamSource)
