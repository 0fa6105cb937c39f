"""Draws the DigiEVISS scene where it is on the stage: spheres (brighter while held), links as
dotted lines between their centres, and a small cursor per tracked hand (Figures 47-49), in its
user's colour."""
from __future__ import annotations

import math

import numpy as np

from effects.gl import Sprites
from host import DepthFrame, Stage, user_colour

SPHERE = (0.2, 0.45, 1.0)
HELD = (0.45, 0.8, 1.0)
LINK = (0.6, 0.85, 1.0)
LINK_DOT_PX = 6.0


class SceneView:
    def __init__(self, stage: Stage) -> None:
        self.stage = stage
        self.discs = Sprites(stage.ctx, softness=0.35)
        self.dots = Sprites(stage.ctx, softness=0.2)

    def _project(self, position, depth: DepthFrame) -> tuple[float, float]:
        return self.stage.to_stage(position, depth)

    def draw(self, scene, target) -> None:
        frame = target.frame
        if frame is None or frame.depth is None:
            return
        depth = frame.depth
        held = {id(g.sphere) for g in scene.grips.values()}
        where = {s.id: np.array(self._project(s.center, depth)) for s in scene.spheres}
        radii = [math.dist(where[s.id], self._project((s.center[0] + s.radius, *s.center[1:]), depth))
                 for s in scene.spheres]
        colours = [(*(HELD if id(s) in held else SPHERE), 0.9) for s in scene.spheres]
        self.discs.draw(target, np.array(list(where.values())), np.array(radii), np.array(colours))
        dots = [where[a] + (where[b] - where[a]) * k for a, b in scene.links() for k in np.linspace(0, 1, 24)]
        hands = [(hand, p) for hand, p in scene.hands.items() if p[2] > 0]
        cursors = [self._project(p, depth) for _, p in hands]
        points = dots + cursors
        if points:
            sizes = [LINK_DOT_PX / 2] * len(dots) + [LINK_DOT_PX * 1.5] * len(cursors)
            rgba = [(*LINK, 1.0)] * len(dots) + [(*user_colour(hand.user), 1.0) for hand, _ in hands]
            self.dots.draw(target, np.array(points), np.array(sizes), np.array(rgba))

    def release(self) -> None:
        self.discs.release()
        self.dots.release()
