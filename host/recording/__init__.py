"""Recordings: depth, hands, gestures and metrics in MCAP (format: see codec.py).

`issv record` writes them; the `replay` backend plays them back as tracked; the `recording`
source feeds their depth to any backend; `issv compare` runs several backends on one.
"""
from host.recording.reader import Recording, shifted_depth, shifted_frame
from host.recording.writer import RecordingWriter

__all__ = ["Recording", "RecordingWriter", "shifted_depth", "shifted_frame"]
