"""Snake: the game alone, no input and no display (the thesis' Snake and Game classes).

The board is a grid of cells; the snake moves one cell per step, `speed` steps per second of game
time. It grows by one when it eats the food and dies when it hits a wall or itself.
"""
from __future__ import annotations

import random
from collections import deque
from enum import Enum


class Direction(Enum):
    UP = (0, -1)
    DOWN = (0, 1)
    LEFT = (-1, 0)
    RIGHT = (1, 0)


class Game:
    def __init__(self, width: int = 20, height: int = 12, speed: float = 4.0, seed: int = 0) -> None:
        self.width, self.height, self.speed = width, height, speed
        self.rng = random.Random(seed)
        x, y = width // 2, height // 2
        self.body: deque[tuple[int, int]] = deque([(x - 2, y), (x - 1, y), (x, y)])  # tail ... head
        self.direction = self.heading = Direction.RIGHT
        self.alive = True
        self.score = 0
        self.steps = 0
        self.clock: float | None = None  # game time of the last step
        self.food = self._place_food()

    @property
    def head(self) -> tuple[int, int]:
        return self.body[-1]

    def turn(self, direction: Direction) -> None:
        """Steer; turning straight back into the snake's own neck is ignored, as in the original."""
        dx, dy = direction.value
        hx, hy = self.heading.value
        if (dx, dy) != (-hx, -hy):
            self.direction = direction

    def step(self) -> None:
        if not self.alive:
            return
        dx, dy = self.direction.value
        x, y = self.head[0] + dx, self.head[1] + dy
        self.heading = self.direction
        self.steps += 1
        grows = (x, y) == self.food
        body = list(self.body) if grows else list(self.body)[1:]
        if not (0 <= x < self.width and 0 <= y < self.height) or (x, y) in body:
            self.alive = False
            return
        self.body.append((x, y))
        if grows:
            self.score += 1
            self.food = self._place_food()
        else:
            self.body.popleft()

    def advance(self, now: float) -> int:
        """Run the steps due by game time `now` (seconds); returns how many were taken."""
        if self.clock is None:
            self.clock = now
        taken = 0
        while self.alive and now - self.clock >= 1.0 / self.speed:
            self.clock += 1.0 / self.speed
            self.step()
            taken += 1
        return taken

    def _place_food(self) -> tuple[int, int]:
        free = [(x, y) for x in range(self.width) for y in range(self.height) if (x, y) not in self.body]
        return self.rng.choice(free)
