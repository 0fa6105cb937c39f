"""The snake game of ch. 5.6: the game, its keyboard controller, and the swipe version (< 20 lines)."""
import curses
from pathlib import Path

import pytest

from host import Gesture, GestureState, GestureType, Stage
from host.assemble import make_backend
from host.loop import EffectSlot, Show
from host.profile import parse

SNAKE = Path(__file__).resolve().parents[2] / "examples" / "snake"


@pytest.fixture(autouse=True)
def snake_on_path(monkeypatch):
    monkeypatch.syspath_prepend(str(SNAKE))


def test_the_snake_moves_turns_eats_and_dies():
    from snake_game.game import Direction, Game
    game = Game(width=10, height=5, seed=3)
    assert list(game.body) == [(3, 2), (4, 2), (5, 2)]
    game.turn(Direction.LEFT)  # straight back into its neck: ignored
    game.step()
    assert game.head == (6, 2)
    game.food = (6, 1)
    game.turn(Direction.UP)
    game.step()
    assert game.head == (6, 1) and len(game.body) == 4 and game.score == 1 and game.food not in game.body
    game.step()
    assert game.alive and game.head == (6, 0)
    game.step()  # through the top wall
    assert not game.alive and game.head == (6, 0)


def test_game_time_sets_the_pace():
    from snake_game.game import Game
    game = Game(speed=4.0)
    assert [game.advance(t) for t in (10.0, 10.2, 10.26, 11.0)] == [0, 0, 1, 3]


def test_the_keyboard_controller_steers_and_quits():
    from snake_game.display import board
    from snake_game.game import Direction, Game
    from snake_game.keyboard import KeyboardController
    game, keys = Game(), KeyboardController()
    assert keys.handle_input(curses.KEY_UP, game) and game.direction is Direction.UP
    assert keys.handle_input(-1, game) and game.direction is Direction.UP  # no key pressed
    assert not keys.handle_input(ord("q"), game)
    *grid, status = board(game).splitlines()
    text = "".join(grid)
    assert status == "score 0" and text.count("@") == 1 and text.count("o") == 2 and text.count("*") == 1


def test_the_swipe_version_is_under_20_lines():
    lines = [line for line in (SNAKE / "snake_game" / "swipe_control.py").read_text().splitlines() if line.strip()]
    assert len(lines) < 20


def test_swipes_steer_the_snake():
    from snake_game.game import Direction
    from snake_game.swipe_control import SwipeSnake
    effect = SwipeSnake()
    effect.setup(Stage((64, 48), 30.0, "test"))
    for kind, want in ((GestureType.SWIPE_UP, Direction.UP), (GestureType.SWIPE_DOWN, Direction.UP),
                       (GestureType.SWIPE_RIGHT, Direction.RIGHT), (GestureType.WAVE, Direction.RIGHT)):
        effect.on_gesture(Gesture(kind, GestureState.COMPLETE, (0.0, 0.0, 2000.0)))
        effect.game.step()  # (down right after up would reverse into the neck: ignored)
        assert effect.game.direction is want


def test_the_synthetic_performer_plays_it_through_the_host(tmp_path, capsys):
    from snake_game.game import Direction
    from snake_game.swipe_control import SwipeSnake
    profile = parse('backend = "truth"\n[source]\nname = "synthetic"\nseed = 4\nchoreography = ['
                    '{action = "idle", duration = 0.5}, {action = "swipe_up", hand = "right"}, '
                    '{action = "swipe_left", hand = "left"}, {action = "idle", duration = 1.0}]\n',
                    str(tmp_path / "p.toml"), tmp_path)
    effect = SwipeSnake()
    stage = Stage((64, 48), 1000.0, "truth")
    Show(make_backend(profile, realtime=False), [EffectSlot(effect, "effects[0]")], stage).run()
    game = effect.game
    assert game.direction is Direction.LEFT and game.alive and game.steps > 5
    xs = [x for x, _ in game.body]
    assert game.head[0] == min(xs) and game.head[1] < 6  # went up from row 6, then left
    assert "@" in capsys.readouterr().out  # the board was shown
