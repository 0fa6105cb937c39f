"""FAKE of openni.openni2 (PyPI `openni` 2.3.0), the parts NiTE2's adapter uses.

Test hook: `fake_devices` maps a device URI (bytes) to the FakeScene it "sees"; open_any() opens
the first one. A FakeScene is a list of FakeNiteFrame (see nite2.py) plus the camera intrinsics.
"""
import ctypes
import os

import numpy as np

from openni.utils import HandleObject, InitializationError, OpenNIError  # noqa: F401 (as the real module)

_openni2_initialized = False
loaded_dll_directory = None
fake_devices = {}


def initialize(dll_directories=()):
    """As the real one: find libOpenNI2.so in one of the folders, else InitializationError."""
    global _openni2_initialized, loaded_dll_directory
    if _openni2_initialized:
        return
    if isinstance(dll_directories, str):
        dll_directories = [dll_directories]
    for folder in dll_directories:
        if os.path.isfile(os.path.join(folder, "libOpenNI2.so")):
            loaded_dll_directory, _openni2_initialized = folder, True
            return
    raise InitializationError("OpenNI2 could not be loaded:\n    %s" % ", ".join(dll_directories))


def is_initialized():
    return _openni2_initialized


def unload():
    global _openni2_initialized
    _openni2_initialized = False


class _DeviceInfo(ctypes.Structure):
    _fields_ = [("uri", ctypes.c_char * 256), ("vendor", ctypes.c_char * 256), ("name", ctypes.c_char * 256)]


class Device(HandleObject):
    def __init__(self, uri, mode=None):
        if not _openni2_initialized:
            raise InitializationError("OpenNI2 not initialized")
        if uri is None:
            if not fake_devices:
                raise OpenNIError(1, "DeviceOpen using default: no devices found", "")
            uri = next(iter(fake_devices))
        if uri not in fake_devices:
            raise OpenNIError(1, "Could not open \"%s\": Failed to open device" % uri.decode(), "")
        self.uri = uri
        self.fake_scene = fake_devices[uri]
        self.playback = None
        HandleObject.__init__(self, uri)

    @classmethod
    def open_any(cls):
        return cls(None)

    @classmethod
    def open_file(cls, filename):
        return cls(filename)

    def get_device_info(self):
        return _DeviceInfo(self.uri, b"FAKE", b"FAKE sensor")

    def _close(self):
        self.fake_closed = True


class VideoFrame(HandleObject):
    """As the real one: a frame whose buffer belongs to OpenNI until released."""

    def __init__(self, pixels, timestamp, frame_index):
        self._buffer = np.ascontiguousarray(pixels, dtype=np.uint16)
        self.height, self.width = self._buffer.shape
        self.stride = self.width * 2
        self.dataSize = self._buffer.nbytes
        self.timestamp, self.frameIndex = timestamp, frame_index
        HandleObject.__init__(self, True)

    def get_buffer_as_uint16(self):
        return (ctypes.c_uint16 * (self.dataSize // 2)).from_address(self._buffer.ctypes.data)

    def _close(self):
        self._buffer[...] = 0  # the memory goes back to OpenNI
