"""The original: snake on the arrow keys in a terminal (`python -m snake_game.keyboard`).

`KeyboardController.handle_input` is the thesis' Controller::HandleInput; `swipe_control.py` is
all it takes to play the same game with swipes instead.
"""
from __future__ import annotations

import curses
import time

from snake_game.display import board
from snake_game.game import Direction, Game


class KeyboardController:
    KEYS = {curses.KEY_UP: Direction.UP, curses.KEY_DOWN: Direction.DOWN,
            curses.KEY_LEFT: Direction.LEFT, curses.KEY_RIGHT: Direction.RIGHT,
            ord("w"): Direction.UP, ord("s"): Direction.DOWN, ord("a"): Direction.LEFT, ord("d"): Direction.RIGHT}

    def handle_input(self, key: int, game: Game) -> bool:
        """Steer with a key; False when the player quits (q or Escape)."""
        if key in (ord("q"), 27):
            return False
        if key in self.KEYS:
            game.turn(self.KEYS[key])
        return True


def play(screen: "curses.window") -> int:
    curses.curs_set(0)
    screen.nodelay(True)
    game, controller = Game(), KeyboardController()
    start = time.monotonic()
    while game.alive and controller.handle_input(screen.getch(), game):
        game.advance(time.monotonic() - start)
        screen.erase()
        screen.addstr(0, 0, board(game))
        screen.refresh()
        time.sleep(1 / 60)
    return game.score


if __name__ == "__main__":
    print(f"score {curses.wrapper(play)}")
