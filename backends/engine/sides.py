"""Hand ids by side: the open engine's hands renamed as a mode names them.

The skeleton (skeleton.py) reports a left and a right hand for as long as the user is in view,
resting ones measured where they hang, each with one id per side (10 * user + 1 or + 2, as
backends/users.py). Gestures are made by the tracker's extended-hand tracks; they are renamed to
the id of their user's hand on their side, so an effect finds the hand that made a gesture among
the frame's hands. Nuitrack mode numbers the hands as the Nuitrack adapter does: user 1 left 1,
right 2; user n 2n - 1 and 2n.
"""
from __future__ import annotations

from dataclasses import replace
from typing import Callable

from backends.users import hand_id
from host import Gesture, Hand, Side

NUITRACK_IDS = {Side.LEFT: 1, Side.RIGHT: 2}

#: (user, side) -> the hand's id; None for a hand without a side (it keeps its own id)
HandIds = Callable[[int, Side], "int | None"]


def user_hand_id(user: int, side: Side) -> int | None:
    """The engine's id of a user's hand on a side."""
    return hand_id(user, side) if side in NUITRACK_IDS else None


def nuitrack_id(user: int, side: Side) -> int | None:
    return 2 * (user - 1) + NUITRACK_IDS[side] if side in NUITRACK_IDS else None


def renamed_gesture(g: Gesture, ids: HandIds) -> Gesture:
    """The gesture, naming its hand by its user's hand on its side."""
    new = ids(g.user_id, g.side)
    return g if new is None else replace(g, hand_id=new)


def renamed_hand(h: Hand, ids: HandIds) -> Hand:
    new = ids(h.user_id, h.side)
    return h if new is None else replace(h, id=new)
