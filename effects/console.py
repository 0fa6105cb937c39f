"""`console`: prints user, hand and gesture events as they happen, like the thesis' sample application.

A backend that tracks users reports both hands all the time, resting at the sides included, so
an arm coming down is no event: a user appears (`user 1 new`) with their hands, and leaves
(`user 1 lost`) with them. A backend that knows only hands shows each hand's coming and going.
"""
from __future__ import annotations

import json
import sys
from typing import Literal

from pydantic import BaseModel, ConfigDict

from host import Effect, Frame, Gesture, HandState, User


class ConsoleOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")
    format: Literal["text", "json"] = "text"
    hands: bool = True  # user and hand events (new, lost), not only gestures
    in_progress: bool = False


class ConsoleEffect(Effect):
    name = "console"
    Options = ConsoleOptions

    def setup(self, stage) -> None:
        super().setup(stage)
        self._known: dict[int, HandState] = {}
        self._users: set[int] = set()

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
        """User and hand events (new, lost): the SimpleOpenNI onNewUser / onLostUser and
        onNewHand / onLostHand of the sample app."""
        if not self.options.hands:
            return
        self._user_events(frame)
        seen = {}
        for hand in frame.hands:
            if not hand.in_view:
                continue
            seen[hand.id] = hand.state
            if hand.id not in self._known:
                user = hand.user_id if frame.users else None
                self._line(frame, "hand", hand.id, "new", hand.position, hand.side.value, user)
        for hand_id in sorted(self._known.keys() - seen.keys()):
            self._line(frame, "hand", hand_id, "lost")
        self._known = seen

    def _user_events(self, frame: Frame) -> None:
        in_view: dict[int, User] = {u.id: u for u in frame.users if u.in_view}
        for user in in_view.values():
            if user.id not in self._users:
                self._line(frame, "user", user.id, "new", user.center_of_mass)
        for user_id in sorted(self._users - in_view.keys()):
            self._line(frame, "user", user_id, "lost")
        self._users = set(in_view)

    def _line(self, frame: Frame, kind: str, number: int, what: str, position=None, side: str = "",
              user: int | None = None) -> None:
        """`user 1 new at (x, y, z) mm`, `hand 12 new  right   of user 1 at ...`, `hand 2 lost`."""
        if self.options.format == "json":
            doc = {"t": round(frame.timestamp, 4), "type": f"{kind}_{what}", kind: number}
            if kind == "hand":
                doc["side"] = side
                if user is not None:
                    doc["user"] = user
            doc["position"] = position and [round(c, 1) for c in position]
            self._print(json.dumps(doc))
            return
        whose = f"{side:<7} " if side else ""
        whose += f"of user {user} " if user is not None else ""
        where = f"at ({position[0]:.0f}, {position[1]:.0f}, {position[2]:.0f}) mm" if position else ""
        self._print(f"{frame.timestamp:8.2f}s  {kind} {number} {what:<4} {whose}{where}".rstrip())
