"""Trajectories the learned-gesture tests write themselves: a performer in `t,hand,x,y,z` CSV
(mirrored: +x is the performer's right), repeating a motion with rest between repetitions."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

REST = np.array([[-0.35, -0.65, -0.1], [0.35, -0.65, -0.1]])  # hands hanging, body units from the torso


def circle(u: float) -> np.ndarray:
    """Both hands up in front of the chest, rolling round each other once, back down."""
    lift = np.sin(np.pi * u) ** 0.5
    a = 2 * np.pi * u
    left = [-0.15 + 0.2 * np.cos(a), 0.1 + 0.2 * np.sin(a), -0.6]
    right = [0.15 - 0.2 * np.cos(a), 0.1 - 0.2 * np.sin(a), -0.6]
    return REST + lift * (np.array([left, right]) - REST)


def punch(u: float) -> np.ndarray:
    """The right hand thrust forward at shoulder height and back; the left stays down."""
    reach = np.sin(np.pi * u)
    out = REST.copy()
    out[1] = REST[1] + reach * (np.array([0.15, 0.45, -1.2]) - REST[1])
    return out


def right_hand_through(u: float, keys: list[tuple[float, list[float]]]) -> np.ndarray:
    """The right hand eased through `keys` ((u, place) in body units), the left hanging at rest."""
    out = REST.copy()
    for (u0, p0), (u1, p1) in zip(keys, keys[1:]):
        if u0 <= u <= u1:
            s = (u - u0) / (u1 - u0)
            out[1] = np.array(p0) + (3 * s * s - 2 * s ** 3) * (np.array(p1) - np.array(p0))
    return out


def throw(u: float) -> np.ndarray:
    """The right hand back over the shoulder, thrown forward, held up in front, then down."""
    held = [0.25, 1.2, -1.2]
    return right_hand_through(u, [(0.0, REST[1]), (0.3, [0.45, 1.5, 0.4]), (0.5, held), (0.85, held), (1.0, REST[1])])


def raise_hand(u: float) -> np.ndarray:
    """The right hand raised straight up in front and held there, where `throw` ends up, then down."""
    held = [0.3, 1.25, -1.0]
    return right_hand_through(u, [(0.0, REST[1]), (0.3, held), (0.85, held), (1.0, REST[1])])


def still(u: float) -> np.ndarray:
    return REST.copy()


@dataclass
class Performer:
    size_mm: float = 520.0  # head-torso distance: the body's size
    distance_mm: float = 2500.0
    speed: float = 1.0  # 2: twice as fast as the teacher
    walk_mm_s: float = 0.0  # the whole body moving sideways
    fps: float = 30.0
    noise_mm: float = 5.0
    seed: int = 0

    def frames(self, motion, repetitions: int, length_s: float = 1.6, rest_s: float = 1.5):
        """(t, {point: xyz}) at fps: rest, then `repetitions` times the motion followed by rest.
        Returns the frames and the times each repetition is half way through."""
        rng = np.random.default_rng(self.seed)
        length, out, middles, t = length_s / self.speed, [], [], 0.0
        plan = [(still, rest_s)] + [step for _ in range(repetitions) for step in ((motion, length), (still, rest_s))]
        for shape, duration in plan:
            if shape is motion:
                middles.append(t + duration / 2)
            for k in range(int(round(duration * self.fps))):
                torso = np.array([self.walk_mm_s * t, 100.0, self.distance_mm])
                hands = shape(k / (duration * self.fps)) * self.size_mm + torso
                points = {"left": hands[0], "right": hands[1], "torso": torso,
                          "head": torso + [0.0, self.size_mm, -20.0]}
                out.append((t, {n: p + rng.normal(0, self.noise_mm, 3) for n, p in points.items()}))
                t += 1.0 / self.fps
        return out, middles

    def write(self, path: Path, motion, repetitions: int, body: bool = True, **kw) -> list[float]:
        """The CSV; body=False leaves out the torso and head rows (a tracker that sees hands only)."""
        frames, middles = self.frames(motion, repetitions, **kw)
        lines = ["t,hand,x,y,z"] + [f"{t:.4f},{n},{p[0]:.1f},{p[1]:.1f},{p[2]:.1f}"
                                    for t, points in frames for n, p in points.items()
                                    if body or n in ("left", "right")]
        path.write_text("\n".join(lines) + "\n")
        return middles
