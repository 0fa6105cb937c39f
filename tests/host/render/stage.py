"""Helpers for render tests: a real headless EGL show driven by scripted frames, read back as pixels.

`ScriptedBackend` is a fake backend (it replays frames the test wrote, no tracking) so that the
pixels can be predicted exactly; everything else, the loop, the renderer, Mesa's EGL, is real.
"""
from __future__ import annotations

import functools
import json
import time
from pathlib import Path

import cv2
import numpy as np
import pytest

from host import (Backend, DepthFrame, Effect, Frame, Gesture, GestureState, GestureType, Hand, HandState,
                  Intrinsics, Side, Stage)
from host.loop import EffectSlot, Show
from host.profile import Output

SIZE = (160, 120)
K = Intrinsics(140.0, 140.0, 80.0, 60.0)
WALL_MM = 2500


@functools.cache
def gl_problem() -> str | None:
    """None when a headless EGL context can be created here, else why not."""
    try:
        import moderngl
        moderngl.create_context(standalone=True, backend="egl").release()
        return None
    except Exception as error:  # pragma: no cover - only where Mesa's EGL is missing
        return f"no headless EGL context ({error}); install libegl1 libegl-mesa0 libgl1-mesa-dri"


requires_gl = pytest.mark.skipif(gl_problem() is not None, reason=str(gl_problem()))


def depth_image(performer: tuple[int, int, int, int] = (60, 20, 100, 110), mm: int = WALL_MM) -> np.ndarray:
    """No reading (0) everywhere but a performer-sized box (u0, v0, u1, v1) at `mm`."""
    depth = np.zeros((SIZE[1], SIZE[0]), np.uint16)
    u0, v0, u1, v1 = performer
    depth[v0:v1, u0:u1] = mm
    return depth


def frames_with_hand(positions: list[tuple[float, float, float]], gestures: dict[int, list[Gesture]] | None = None,
                     mask: np.ndarray | None = None) -> list[Frame]:
    """One frame per right-hand position (mm), with the box performer and optional gestures."""
    out = []
    for i, p in enumerate(positions):
        depth = DepthFrame(depth_image(), K, frame_id=i, timestamp=i / 30)
        hands = (Hand(1, HandState.NEW if i == 0 else HandState.TRACKING, p, Side.RIGHT),)
        out.append(Frame(i + 1, depth.capture_time, depth, hands, tuple((gestures or {}).get(i, ())), "scripted",
                         make_user_mask=None if mask is None else (lambda: mask)))
    return out


def gesture_at(name: str, position: tuple[float, float, float]) -> Gesture:
    return Gesture(GestureType.from_canonical(name), GestureState.COMPLETE, position, 1, Side.RIGHT, 1.0)


class ScriptedBackend(Backend):
    """Fake backend: hands over the frames it was given, one per update(), then ends."""

    name = "scripted"
    needs_source = False

    def __init__(self, frames: list[Frame], period: float = 0.02) -> None:
        super().__init__(None)
        self.frames = list(frames)
        self.period = period  # slower than the show loop, so every frame reaches the effects

    def update(self) -> Frame | None:
        time.sleep(self.period)
        return self.frames.pop(0) if self.frames else None


def run_show(effects: list[Effect | tuple[Effect, str, float]], frames: list[Frame], tmp_path: Path,
             size: tuple[int, int] = (320, 240), **output: object) -> tuple[np.ndarray, Show, Stage]:
    """Plays `frames` through `effects` (or (effect, blend, opacity)) headless; returns the last
    frame as shown (BGR, row 0 at the top), the show and its stage."""
    from host.render import make_renderer

    snapshot = tmp_path / "last.png"
    out = Output(**{"size": size, "mode": "headless", "hud": False, "snapshot": str(snapshot), "fps": 240, **output})
    stage = Stage(size=size, fps=out.fps, backend="scripted")
    renderer = make_renderer(out, stage)
    slots = []
    for i, e in enumerate(effects):
        effect, blend, opacity = e if isinstance(e, tuple) else (e, "normal", 1.0)
        slots.append(EffectSlot(effect, f"effects[{i}]", blend, opacity))
    show = Show(ScriptedBackend(frames), slots, stage, renderer=renderer)
    show.run()
    image = cv2.imread(str(snapshot))
    assert image is not None, "the snapshot was not written"
    return image, show, stage


def lit(image: np.ndarray, xy: tuple[float, float], radius: int = 1) -> np.ndarray:
    """The brightest BGR pixel around (x, y) in image pixels."""
    x, y = int(round(xy[0])), int(round(xy[1]))
    patch = image[max(0, y - radius): y + radius + 1, max(0, x - radius): x + radius + 1].reshape(-1, 3)
    return patch[np.argmax(patch.sum(axis=1))]


def depth_view_profile(tmp_path: Path, frames: int, name: str = "show.toml", loop: bool = False, **output) -> Path:
    """A profile file: a generated clip through `truth` into one depth-view layer; `output` keys
    (mode, hud, size, ...) go into [output]."""
    from tests.conftest import write_clip

    clip = write_clip(tmp_path / "clip.npz", frames=frames)
    keys = "\n".join(f"{key} = {json.dumps(value)}" for key, value in output.items())
    path = tmp_path / name
    path.write_text(f'backend = "truth"\n[source]\nname = "clip"\npath = "{clip}"\nloop = {json.dumps(loop)}\n'
                    f'[[effects]]\nname = "depth-view"\n[output]\n{keys}\n')
    return path
