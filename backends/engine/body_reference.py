"""Where the performer's body is, so that the recogniser judges hand motion relative to it.

With a skeleton (torso, head) the reference is given. Without one it is estimated from the
hands alone: the body's motion is the motion that all hands share (walking moves both hands the
same way; a swipe moves one), followed no faster than a body can accelerate (a push of both
hands is far quicker than a step), and its height comes from the lowest hand, which usually hangs at
rest. No per-clip statistics: everything is a running estimate with physical constants.
"""
from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from typing import Mapping

import numpy as np

from backends.engine.rules import GestureRules


@dataclass(frozen=True)
class BodyFrame:
    """The body at one instant: torso and head centre (mm), the height of the shoulder line, and
    the torso's vertical speed (mm/s)."""

    torso: np.ndarray
    shoulder_y: float
    head: np.ndarray
    vy: float = 0.0


def _shared(velocities: list[np.ndarray]) -> np.ndarray:
    """Per axis: the smallest velocity if all hands agree in sign, else 0 (what they all share)."""
    v = np.array(velocities)
    same = np.all(v > 0, axis=0) | np.all(v < 0, axis=0)
    return np.where(same, np.sign(v[0]) * np.min(np.abs(v), axis=0), 0.0)


class BodyReference:
    """Fed each frame's hands and optional body points; says where the body is."""

    def __init__(self, rules: GestureRules) -> None:
        self.rules = rules
        self._t: float | None = None
        self._last: dict[int, np.ndarray] = {}
        self._offset = np.zeros(3)  # estimated body displacement since the start (no skeleton)
        self._velocity = np.zeros(3)
        self._recent: deque[tuple[float, float, float, float]] = deque()  # t, mean x, lowest y, furthest z
        self._heights: deque[tuple[float, float]] = deque()  # t, torso y: its vertical speed
        self._given: tuple | None = None  # the last body points given: t, torso, head
        self.measured = False  # the last frame's body came from body points, not from the hands

    def update(self, t: float, hands: Mapping[int, np.ndarray], body: Mapping[str, tuple]) -> BodyFrame:
        r = self.rules
        self._follow(t, hands)
        torso, head = body.get("torso"), body.get("head")
        if torso is not None or head is not None:
            self._given = (t, torso, head)
        elif self._given is not None and t - self._given[0] <= r.body_hold_s:
            _, torso, head = self._given  # a skeleton missing for a moment: the body has not moved
        self.measured = torso is not None or head is not None
        if torso is None and head is None:  # estimated: its vertical speed is unknown, say steady
            estimate = self._estimate()
            torso = estimate if estimate is not None else np.zeros(3)
            return self._frame(torso, torso + self._up, 0.0)
        if torso is not None:
            torso = np.asarray(torso, dtype=float)
            head = np.asarray(head, dtype=float) if head is not None else torso + self._up
        else:
            head = np.asarray(head, dtype=float)
            torso = head - self._up
        return self._frame(torso, head, self._vertical_speed(t, float(torso[1])))

    @property
    def _up(self) -> np.ndarray:
        """From the torso to the head centre of a standing adult (without a skeleton to tell)."""
        return np.array([0.0, self.rules.head_above_torso_mm, 0.0])

    def _frame(self, torso: np.ndarray, head: np.ndarray, vy: float) -> BodyFrame:
        """The shoulder line lies `shoulder_below_head_mm` below the head for an adult, scaled to the
        performer's size like every distance threshold (a child's shoulders are nearer its head)."""
        size = self.rules.size(float(head[1] - torso[1]))
        return BodyFrame(torso, float(head[1]) - self.rules.shoulder_below_head_mm * size, head, vy)

    def _vertical_speed(self, t: float, y: float) -> float:
        self._heights.append((t, y))
        while len(self._heights) > 2 and t - self._heights[1][0] >= self.rules.body_speed_window_s:
            self._heights.popleft()
        t0, y0 = self._heights[0]
        return (y - y0) / (t - t0) if t > t0 else 0.0

    def _follow(self, t: float, hands: Mapping[int, np.ndarray]) -> None:
        """Every frame: the body's motion shared by the hands, and the recent resting-hand figures."""
        r = self.rules
        if self._t is not None and t > self._t:
            dt = t - self._t
            moved = [(p - self._last[i]) / dt for i, p in hands.items() if i in self._last]
            shared = _shared(moved) if len(moved) >= 2 else np.zeros(3)
            shared[1] = 0.0  # raising both arms is common; rising or sinking bodies are rare: height comes from rest
            # a body accelerates slowly; hands pushing together do not drag it along
            step = r.body_max_acceleration_mm_s2 * dt
            self._velocity = self._velocity + np.clip(shared - self._velocity, -step, step)
            self._offset = self._offset + self._velocity * dt
        self._t = t
        self._last = dict(hands)
        if hands:
            rel = np.array([p - self._offset for p in hands.values()])
            self._recent.append((t, float(rel[:, 0].mean()), float(rel[:, 1].min()), float(rel[:, 2].max())))
        while self._recent and t - self._recent[0][0] > r.body_window_s:
            self._recent.popleft()

    def _estimate(self) -> np.ndarray | None:
        """The body from the hands alone (only needed without body points)."""
        r = self.rules
        if not self._recent:
            return None
        rec = np.array(self._recent)
        return self._offset + np.array([rec[:, 1].mean(),
                                        rec[:, 2].min() + r.rest_below_torso_mm,
                                        rec[:, 3].max() + r.rest_in_front_of_torso_mm])
