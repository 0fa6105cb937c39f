"""Hand ids by side: the open engine's hands renamed as a mode names them.

The skeleton (skeleton.py) reports a left and a right hand for as long as the user is in view,
resting ones measured where they hang, each with one id per side (10 * user + 1 or + 2, as
backends/users.py). Gestures are made by the tracker's extended-hand tracks; they are renamed to
the id of their side's hand, so an effect finds the hand that made a gesture among the frame's
hands. Nuitrack mode numbers user 1's hands as the Nuitrack adapter does: left 1, right 2.
"""
from __future__ import annotations

from dataclasses import replace
from typing import Callable

from backends.users import hand_id
from host import Gesture, Hand, Side

NUITRACK_IDS = {Side.LEFT: 1, Side.RIGHT: 2}


def user_hand_id(user: int) -> Callable[[Side], int | None]:
    """The id of a user's hand on a side (None: no side, the gesture keeps its hand's id)."""
    return lambda side: hand_id(user, side) if side in (Side.LEFT, Side.RIGHT) else None


def nuitrack_id(side: Side) -> int | None:
    return NUITRACK_IDS.get(side)


def renamed_gesture(g: Gesture, ids: Callable[[Side], int | None]) -> Gesture:
    """The gesture, naming its hand by its side's id."""
    new = ids(g.side)
    return g if new is None else replace(g, hand_id=new)


def renamed_hand(h: Hand, ids: Callable[[Side], int | None]) -> Hand:
    new = ids(h.side)
    return h if new is None else replace(h, id=new)
