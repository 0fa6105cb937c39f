"""Short synthetic performances for the tracker and backend tests (real rendered depth, with truth)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from host import DepthFrame
from sources.synthetic import SyntheticOptions, SyntheticSource
from sources.synthetic.source import CAMERA_HEIGHT_MM

WAVE_THEN_REST = [{"action": "idle", "duration": 0.5}, {"action": "wave"}, {"action": "idle", "duration": 1.5}]
SWIPE = [{"action": "idle", "duration": 0.4}, {"action": "swipe_left"}, {"action": "idle", "duration": 0.5}]


def idle(seconds: float) -> dict:
    return {"action": "idle", "duration": seconds}


def walk(x_mm: float, seconds: float) -> dict:
    return {"action": "walk", "x_mm": x_mm, "duration": seconds}


def frames(steps: list[dict] | None = None, seed: int = 3, wall_mm: float | None = None,
           **options) -> list[DepthFrame]:
    """Every frame of a seeded synthetic performance (640x480 with floor and back wall unless
    told): one performer's `steps`, or several in `performers`, each with its truth in Truth.users.
    `wall_mm`: the back wall this far from the camera (the source puts it 1.5 m behind the farthest
    performer)."""
    if steps is not None:
        options["choreography"] = steps
    source = SyntheticSource(SyntheticOptions(seed=seed, **options))
    source.open()
    if wall_mm is not None:
        source.room = source.raster.room(-CAMERA_HEIGHT_MM, wall_mm)
    out = []
    while (frame := source.read()) is not None:
        out.append(frame)
    source.close()
    return out


def write_clip(path: Path, depth_frames: list[DepthFrame]) -> Path:
    """The frames as a depth clip (.npz, docs/architecture.md) with hand truth, as a recording would be."""
    first = depth_frames[0]
    hands = np.full((len(depth_frames), 2, 3), np.nan)
    for i, f in enumerate(depth_frames):
        for k, side in enumerate(("left", "right")):
            for s, p in (f.truth.hands.items() if f.truth else ()):
                if s.value == side:
                    hands[i, k] = p
    np.savez(path, depth=np.stack([f.data for f in depth_frames]),
             timestamps=np.array([f.timestamp for f in depth_frames]),
             intrinsics=np.array(first.intrinsics.as_list()), mirrored=first.mirrored,
             hands=hands, hand_names=np.array(["left", "right"]))
    return path


def swipe_cut_short(path: Path) -> Path:
    """A clip of one swipe that stops while the swipe waits for its confirmation (the 0.12 s in
    which a comparable stroke back would make it a wind-up): only the clip's end completes it."""
    swipe = frames(SWIPE, background="none")
    cut = max(i for i, f in enumerate(swipe) if f.truth.gestures) + 6  # the stroke's stop is seen 4-5 frames on
    return write_clip(path, swipe[:cut])
