"""A third-party issv plugin: appends every completed gesture to a text file, and adds the
command `issv gesture-log FILE` that counts the gestures in such a file."""
import argparse
import sys
from collections import Counter
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


class GestureLogCommand:
    """`issv gesture-log FILE`: how often each gesture was logged."""

    NAME = "gesture-log"
    HELP = "count the completed gestures in a gesture-log file"

    @staticmethod
    def add_arguments(parser: argparse.ArgumentParser) -> None:
        parser.add_argument("file", type=Path, help="a file written by the gesture-log effect")

    @staticmethod
    def main(args: argparse.Namespace) -> int:
        counts = Counter(line.split()[1] for line in args.file.read_text().splitlines() if line.strip())
        for name, count in sorted(counts.items()):
            sys.stdout.write(f"{name} {count}\n")
        return 0


@hookimpl
def register_effects(register):
    register(GestureLog)


@hookimpl
def register_commands(register):
    register(GestureLogCommand)
