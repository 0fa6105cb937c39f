"""Interactive calibration in the show window (`issv calibrate PROFILE` without --points).

Drag the four corner handles with the mouse until the projected image fills the screen or wall
(the keystone). Then hold a hand still for a second on each projected target: the tracked hand's
depth pixel and the target's stage pixel make one point pair. Enter saves (the keystone, and the
calibration once >= 4 targets are done), Backspace takes the last point back, Escape cancels.
The picture is drawn with OpenCV and shown through the keystone, so what you drag is what the
audience will see.
"""
from __future__ import annotations

import sys
import time
from collections import deque

import cv2
import numpy as np

from host.app import check_sensor
from host.assemble import make_backend, make_stage
from host.errors import UserError
from host.loop import Show
from host.model import Frame
from host.plugins import default_manager
from host.profile import Profile
from host.render.calibration import UNIT_SQUARE, check_keystone, homography
from host.render.context import Window
from host.render.warp import Keystone

TARGETS = ((0.2, 0.2), (0.8, 0.2), (0.8, 0.8), (0.2, 0.8), (0.5, 0.5))  # stage fractions
HOLD_S = 1.0  # a hand held this long ...
HOLD_MM = 30.0  # ... within this distance is on the target
GRAB_PX = 30


class Session:
    """The state of one calibration: corners, targets reached, the hand being held."""

    def __init__(self, size: tuple[int, int], corners) -> None:
        self.size = size
        self.corners = [list(c) for c in (corners or UNIT_SQUARE)]
        self.pairs: list[tuple[tuple[float, float], tuple[float, float]]] = []  # (depth uv, stage px)
        self.held: deque[tuple[float, tuple[float, float, float]]] = deque()
        self.dragging: int | None = None

    @property
    def target(self) -> tuple[float, float] | None:
        if len(self.pairs) >= len(TARGETS):
            return None
        fx, fy = TARGETS[len(self.pairs)]
        return (fx * self.size[0], fy * self.size[1])

    def hand(self, frame: Frame | None, now: float) -> None:
        """Records a pair when the hand has stayed on the current target for HOLD_S."""
        hands = [h for h in (frame.hands if frame else ()) if h.in_view]
        if not hands or frame.depth is None or self.target is None:
            self.held.clear()
            return
        p = hands[0].position
        self.held.append((now, p))
        while self.held and np.linalg.norm(np.subtract(self.held[0][1], p)) > HOLD_MM:
            self.held.popleft()
        if now - self.held[0][0] >= HOLD_S:
            u, v, _ = frame.depth.world_to_depth(p)
            self.pairs.append(((u, v), self.target))
            self.held.clear()

    def press(self, x: float, y: float) -> None:
        w, h = self.size
        near = [np.hypot(cx * w - x, cy * h - y) for cx, cy in self.corners]
        self.dragging = int(np.argmin(near)) if min(near) < GRAB_PX else None

    def drag(self, x: float, y: float) -> None:
        """Moves the grabbed corner, as long as the four still make a convex quad."""
        if self.dragging is None:
            return
        corners = [list(c) for c in self.corners]
        corners[self.dragging] = [min(max(x / self.size[0], 0.0), 1.0), min(max(y / self.size[1], 0.0), 1.0)]
        try:
            check_keystone(corners)
        except UserError:
            return
        self.corners = corners

    def result(self) -> dict[str, object]:
        out: dict[str, object] = {"keystone": [[round(v, 5) for v in c] for c in self.corners]}
        if len(self.pairs) >= 4:
            cam, stage = zip(*self.pairs)
            out["calibration"] = [[float(f"{v:.9g}") for v in row] for row in homography(cam, stage)]
        return out

    def picture(self, frame: Frame | None) -> np.ndarray:
        """The stage: targets, progress and instructions (the corner handles are drawn unwarped)."""
        w, h = self.size
        img = np.zeros((h, w, 4), np.uint8)
        cv2.rectangle(img, (2, 2), (w - 3, h - 3), (255, 255, 255, 255), 2)
        for i, (fx, fy) in enumerate(TARGETS):
            done = i < len(self.pairs)
            colour = (80, 200, 80, 255) if done else (255, 255, 255, 255)
            centre = (int(fx * w), int(fy * h))
            cv2.circle(img, centre, int(0.04 * h), colour, 2 if not done else -1, cv2.LINE_AA)
            if self.target is not None and i == len(self.pairs):
                held = 0.0 if not self.held else min(1.0, (self.held[-1][0] - self.held[0][0]) / HOLD_S)
                cv2.ellipse(img, centre, (int(0.06 * h),) * 2, -90, 0, 360 * held, (255, 200, 0, 255), 4)
        lines = ["drag the corners to fit the image; hold a hand still on the ringed target",
                 f"targets done {len(self.pairs)}/{len(TARGETS)}   Enter: save   Backspace: undo   Esc: cancel"]
        for i, text in enumerate(lines):
            cv2.putText(img, text, (20, int(h * 0.45) + 30 * i), cv2.FONT_HERSHEY_SIMPLEX, 0.6, (255, 255, 255, 255), 1, cv2.LINE_AA)
        return img


class CalibrationView:
    """The calibration window as the show's renderer: every tick it takes the newest frame's hand,
    draws the picture through the keystone and presents it; closing the window ends the show."""

    def __init__(self, window: Window, session: Session) -> None:
        self.window = window
        self.session = session
        self.shown = [tuple(c) for c in session.corners]
        self.keystone = Keystone(window.ctx, window.size, self.shown)

    @property
    def wants_stop(self) -> bool:
        return self.window.closing

    def render(self, show: Show, frame: Frame | None) -> None:
        self.session.hand(frame, time.monotonic())
        corners = [tuple(c) for c in self.session.corners]
        if corners != self.shown:  # re-solve and upload the warp only when a corner moved
            self.shown = corners
            self.keystone.set_corners(corners)
        self.keystone.texture.write(np.ascontiguousarray(self.session.picture(frame)[::-1]))
        self.keystone.draw(self.window.fbo)
        self.window.present()

    def close(self) -> None:
        self.keystone.release()
        self.window.close()


def calibrate_interactively(prof: Profile) -> dict[str, object] | None:
    """Runs the calibration window; the keys to save, or None when cancelled."""
    out = prof.model.output
    try:
        window = Window(tuple(out.size), out.mode == "fullscreen", out.monitor, title="issv calibrate")
    except UserError:
        raise
    except Exception as error:  # no display, no GLX: pyglet and moderngl raise many kinds
        raise UserError(f"issv calibrate: cannot open a window ({type(error).__name__}: {error}); "
                        "without a display, calibrate from a points file: --points FILE.csv") from None
    session = Session(window.size, out.keystone)
    result: dict[str, object] | None = None
    keys = window.wnd.keys

    def on_key(key, action, modifiers) -> None:
        nonlocal result
        if action != keys.ACTION_PRESS:
            return
        if key == keys.ENTER:
            result = session.result()
            window.wnd.close()
        elif key == keys.BACKSPACE and session.pairs:
            session.pairs.pop()

    window.wnd.key_event_func = on_key
    window.wnd.mouse_press_event_func = lambda x, y, button: session.press(x, y)
    window.wnd.mouse_drag_event_func = lambda x, y, dx, dy: session.drag(x, y)
    window.wnd.mouse_release_event_func = lambda x, y, button: setattr(session, "dragging", None)

    backend = make_backend(prof)
    view = CalibrationView(window, session)
    # The host's frame loop drives the backend, with the rules it has on stage (a frame it raises
    # on is skipped; failing frame after frame ends the sensor side); the window stays open.
    show = Show(backend, [], make_stage(prof, backend), pm=default_manager(), renderer=view, hold=True)
    show.run()
    if show.sensor_error is not None:
        if result is None:
            check_sensor(show)  # the one line saying which backend failed and why
        print(f"issv calibrate: backend {backend.name!r} failed during calibration "
              f"({type(show.sensor_error).__name__}: {show.sensor_error}); what you saved was set before that",
              file=sys.stderr)
    return result
