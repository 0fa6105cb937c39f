"""Where frames go: a headless EGL context (servers, tests, video) or a window for the projector.

A surface owns the moderngl context and the final framebuffer; `present()` ends a frame.
"""
from __future__ import annotations

import ctypes
import os
import sys
from typing import Callable

import moderngl

from host.errors import UserError

GL_VERSION = 330
EGL_FIX = "install Mesa's EGL (Debian: apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri)"


class Headless:
    """An offscreen RGBA framebuffer on a standalone EGL context (llvmpipe without a GPU)."""

    closing = False

    def __init__(self, size: tuple[int, int]) -> None:
        self.ctx = headless_context()
        self._finish = unlocked_finish() or self.ctx.finish
        self.size = size
        self.fbo = self.ctx.framebuffer([self.ctx.renderbuffer(size, 4)])

    def present(self) -> None:
        """Waits for the GPU (or llvmpipe) so frame times are real and latency stays bounded."""
        self._finish()

    def close(self) -> None:
        self.fbo.release()
        self.ctx.release()


def headless_context() -> moderngl.Context:
    try:
        return moderngl.create_context(standalone=True, backend="egl", require=GL_VERSION)
    except Exception as error:  # moderngl raises bare Exceptions from the loader
        raise UserError(f"issv: cannot create a headless OpenGL {GL_VERSION // 100}.{GL_VERSION % 100 // 10} "
                        f"context through EGL ({error}); {EGL_FIX}") from None


def unlocked_finish() -> Callable[[], None] | None:
    """glFinish called through ctypes, which lets go of the GIL while it waits.

    moderngl holds the GIL in every call; llvmpipe renders on its own threads, so `ctx.finish()`
    would stall the sensor thread (tracking, in Python) for the whole frame's rasterisation.
    """
    try:
        egl = ctypes.CDLL("libEGL.so.1")
        egl.eglGetProcAddress.restype = ctypes.c_void_p
        egl.eglGetProcAddress.argtypes = [ctypes.c_char_p]
        address = egl.eglGetProcAddress(b"glFinish")
    except (OSError, AttributeError):
        return None
    return ctypes.CFUNCTYPE(None)(address) if address else None


class Window:
    """A moderngl-window window on pyglet (moderngl-window's default backend, pure Python wheels);
    fullscreen on the chosen monitor for the projector. Escape or closing the window ends the show."""

    def __init__(self, size: tuple[int, int], fullscreen: bool, monitor: int, title: str = "issv") -> None:
        from moderngl_window.context.pyglet import Window as PygletWindow

        self.wnd = PygletWindow(title=title, size=size, resizable=False, vsync=False, gl_version=(3, 3))
        self.wnd.fullscreen_key = None  # the stage keeps its size: fullscreen is the profile's choice
        if fullscreen:
            self._fullscreen_on(monitor)
        self.ctx = self.wnd.ctx
        self.size = self.wnd.buffer_size
        # Draw offscreen and blit: the back buffer is undefined after a swap, and snapshots and
        # video read the last frame.
        self.fbo = self.ctx.framebuffer([self.ctx.renderbuffer(self.size, 4)])

    def _fullscreen_on(self, monitor: int) -> None:
        import pyglet

        display = pyglet.display.get_display() if hasattr(pyglet, "display") else pyglet.canvas.get_display()
        screens = display.get_screens()
        if monitor >= len(screens):
            self.wnd.destroy()
            raise UserError(f"output.monitor: there is no monitor {monitor}; this machine has {len(screens)} "
                            f"(0..{len(screens) - 1})")
        # moderngl-window's pyglet window only knows the default screen: ask pyglet for the chosen one.
        self.wnd._window.set_fullscreen(True, screen=screens[monitor])
        self.wnd._window.dispatch_events()
        self.wnd.resize(*self.wnd._window.get_framebuffer_size())

    @property
    def closing(self) -> bool:
        return self.wnd.is_closing

    def present(self) -> None:
        self.ctx.copy_framebuffer(self.wnd.fbo, self.fbo)
        self.wnd.swap_buffers()  # also polls the window's events

    def close(self) -> None:
        self.fbo.release()
        self.wnd.destroy()


def open_surface(mode: str, size: tuple[int, int], monitor: int) -> Headless | Window:
    """The surface the profile asks for; without a display, a window falls back to headless."""
    if mode == "headless":
        return Headless(size)
    if sys.platform.startswith("linux") and not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        print("issv: no display (DISPLAY is not set): rendering headless; use --headless to say so",
              file=sys.stderr)
        return Headless(size)
    try:
        return Window(size, mode == "fullscreen", monitor)
    except UserError:
        raise
    except Exception as error:
        print(f"issv: cannot open a window ({type(error).__name__}: {error}); rendering headless",
              file=sys.stderr)
        return Headless(size)
