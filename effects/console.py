"""`console`: prints hand and gesture events as they happen, like the thesis' sample application."""
from __future__ import annotations

import json
import sys
from typing import Literal

from pydantic import BaseModel, ConfigDict

from host import Effect, Frame, Gesture, HandState


class ConsoleOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    format: Literal["text", "json"] = "text"
    hands: bool = True
    in_progress: bool = False


class ConsoleEffect(Effect):
    name = "console"
    Options = ConsoleOptions

    def setup(self, stage) -> None:
        super().setup(stage)
        self._known: dict[int, HandState] = {}

    def _print(self, text: str) -> None:
        print(text, file=sys.stdout, flush=True)

    def on_gesture(self, gesture: Gesture) -> None:
        if gesture.state.value != "complete" and not self.options.in_progress:
            return
        if self.options.format == "json":
            self._print(json.dumps(gesture.to_json()))
            return
        x, y, z = gesture.position
        self._print(f"{gesture.timestamp:8.2f}s  gesture {gesture.name:<11} {gesture.state.value:<11} "
                    f"{gesture.side.value:<7} hand {gesture.hand_id}  at ({x:.0f}, {y:.0f}, {z:.0f}) mm  "
                    f"confidence {gesture.confidence:.2f}")

    def on_frame(self, frame: Frame) -> None:
        """Hand events (new, lost): the SimpleOpenNI onNewHand / onLostHand of the sample app."""
        if not self.options.hands:
            return
        seen = {}
        for hand in frame.hands:
            if not hand.in_view:
                continue
            seen[hand.id] = hand.state
            if hand.id not in self._known:
                self._hand_line(frame, "new", hand.id, hand.side.value, hand.position)
        for hand_id in self._known.keys() - seen.keys():
            self._hand_line(frame, "lost", hand_id, "", None)
        self._known = seen

    def _hand_line(self, frame: Frame, what: str, hand_id: int, side: str, position) -> None:
        if self.options.format == "json":
            self._print(json.dumps({"t": round(frame.timestamp, 4), "type": f"hand_{what}", "hand": hand_id,
                                    "side": side, "position": position and [round(c, 1) for c in position]}))
            return
        where = f"{side:<7} at ({position[0]:.0f}, {position[1]:.0f}, {position[2]:.0f}) mm" if position else ""
        self._print(f"{frame.timestamp:8.2f}s  hand {hand_id} {what:<4} {where}".rstrip())
