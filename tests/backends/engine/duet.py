"""Scenes of several synthetic performers for the engine's tests: each performer rendered by the
synthetic source on its own (the farthest with the room, its wall 1.5 m behind them, the others
alone), then combined per pixel (the nearest reading wins), with every performer's truth in
Truth.users (ids 1, 2, ... in the order given)."""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from host import DepthFrame, Truth, UserTruth
from sources.synthetic import SyntheticOptions, SyntheticSource


def idle(seconds: float) -> dict:
    return {"action": "idle", "duration": seconds}


def walk(x_mm: float, seconds: float) -> dict:
    return {"action": "walk", "x_mm": x_mm, "duration": seconds}


def scene_frames(performers: list[dict], seed: int = 3, **options) -> list[DepthFrame]:
    """Every frame of the performers ({x_mm, distance_mm, choreography, height_mm...}) together."""
    passes = []
    farthest = max(range(len(performers)), key=lambda i: performers[i].get("distance_mm", 2500.0))
    for i, p in enumerate(performers):
        p = dict(p)
        start_x = p.pop("x_mm", 0.0)
        source = SyntheticSource(SyntheticOptions(choreography=p.pop("choreography"), seed=seed + i,
                                                  background="room" if i == farthest else "none", **p, **options))
        source.open()
        source.timeline = source._pass(start_x, 0.0)  # the performer starts at x_mm (the source starts at 0)
        frames = []
        while (frame := source.read()) is not None:
            frames.append(frame)
        passes.append(frames)
    out = []
    for i in range(max(len(f) for f in passes)):
        now = [(uid, f[i]) for uid, f in enumerate(passes, 1) if i < len(f)]
        room = passes[farthest][min(i, len(passes[farthest]) - 1)]
        depth = room.data.copy()
        for _, f in now:
            nearer = (f.data > 0) & ((f.data < depth) | (depth == 0))
            depth[nearer] = f.data[nearer]
        users = tuple(UserTruth(uid, f.truth.hands, f.truth.body, f.truth.gestures) for uid, f in now)
        truth = Truth(users[0].hands, users[0].gestures, users[0].body, users)
        depth.flags.writeable = False
        out.append(replace(room, data=depth, frame_id=i, timestamp=i / 30.0, truth=truth))
    return out
