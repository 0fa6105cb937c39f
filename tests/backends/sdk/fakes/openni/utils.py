"""FAKE of openni.utils (PyPI `openni` 2.3.0): the same errors, handle base class and CEnum."""
import ctypes


class InitializationError(Exception):
    pass


class OpenNIError(Exception):
    def __init__(self, code, message, logfile):
        self.code = code
        self.logfile = logfile
        Exception.__init__(self, code, message, logfile)


class NiteError(Exception):
    def __init__(self, code):
        Exception.__init__(self, code)


class HandleObject(object):
    """As the real one: close() once, then the handle is gone."""

    def __init__(self, handle):
        self._handle = handle

    def __bool__(self):
        return bool(getattr(self, "_handle", None))

    def close(self):
        if getattr(self, "_handle", None):
            self._close()
            self._handle = None

    def _close(self):
        raise NotImplementedError()


class CEnum(ctypes.c_int):
    """As the real CEnum: a c_int whose members compare and convert as ints."""

    def __int__(self):
        return int(self.value)

    def __index__(self):
        return int(self)

    def __eq__(self, other):
        return int(self) == int(other)

    def __hash__(self):
        return hash(int(self))
