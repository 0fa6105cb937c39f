"""A third-party issv plugin: appends every completed gesture to a text file."""
from pathlib import Path

from pydantic import BaseModel, ConfigDict

from host import Effect, Gesture, GestureState, hookimpl
from host.options import ProfilePath


class GestureLogOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    path: ProfilePath = "gestures.log"


class GestureLog(Effect):
    name = "gesture-log"
    Options = GestureLogOptions

    def setup(self, stage) -> None:
        super().setup(stage)
        self._file = Path(self.options.path).open("a", encoding="utf-8")

    def on_gesture(self, gesture: Gesture) -> None:
        if gesture.state is GestureState.COMPLETE:
            self._file.write(f"{gesture.timestamp:.3f} {gesture.name} {gesture.side.value}\n")
            self._file.flush()

    def close(self) -> None:
        self._file.close()


@hookimpl
def register_effects(register):
    register(GestureLog)
