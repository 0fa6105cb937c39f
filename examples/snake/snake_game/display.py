"""The simplest display that works everywhere, tests included: the board as text."""
from __future__ import annotations

from snake_game.game import Game


def board(game: Game) -> str:
    rows = [["."] * game.width for _ in range(game.height)]
    fx, fy = game.food
    rows[fy][fx] = "*"
    for x, y in game.body:
        rows[y][x] = "o"
    hx, hy = game.head
    rows[hy][hx] = "@" if game.alive else "X"
    status = f"score {game.score}" + ("" if game.alive else "  GAME OVER")
    return "\n".join(["+" + "-" * game.width + "+"] + ["|" + "".join(r) + "|" for r in rows]
                     + ["+" + "-" * game.width + "+", status])
