"""FAKE of the PyPI `openni` package (OpenNI2/NiTE2 ctypes bindings): tests only, see ../README.md."""
