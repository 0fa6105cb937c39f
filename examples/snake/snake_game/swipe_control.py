"""Snake on swipes (thesis ch. 5.6, Fig. 65): this file is the whole change from the keyboard."""
from host import Effect, Gesture, GestureState, hookimpl
from snake_game.display import board
from snake_game.game import Direction, Game

SWIPES = {"swipe_up": Direction.UP, "swipe_down": Direction.DOWN,
          "swipe_left": Direction.LEFT, "swipe_right": Direction.RIGHT}


class SwipeSnake(Effect):
    name = "snake"

    def setup(self, stage) -> None:
        self.game = Game(speed=2.0)  # cells/s: a swipe takes longer than a key press

    def on_gesture(self, gesture: Gesture) -> None:
        if gesture.state is GestureState.COMPLETE and gesture.name in SWIPES:
            self.game.turn(SWIPES[gesture.name])

    def on_frame(self, frame) -> None:
        if self.game.advance(frame.timestamp):
            print(board(self.game), flush=True)


@hookimpl
def register_effects(register):
    register(SwipeSnake)
