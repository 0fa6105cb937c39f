"""Hand ids by side: the open engine's gestures (and, in Nuitrack mode, hands) named by side.

The skeleton (skeleton.py) reports a left and a right hand for as long as the user is in view,
resting ones measured where they hang, each with one id per side (`hand_id(user, side)` of
backends/users.py: 10 * user + 1 or + 2). Gestures are made by the tracker's extended-hand
tracks; they are renamed to the id of their user's hand on their side, so an effect finds the
hand that made a gesture among the frame's hands. Nuitrack mode numbers user 1's hands as the
Nuitrack adapter does: left 1, right 2.
"""
from __future__ import annotations

from dataclasses import replace
from typing import Callable

from backends.users import hand_id
from host import Gesture, Hand, Side

NUITRACK_IDS = {Side.LEFT: 1, Side.RIGHT: 2}
SIDES = (Side.LEFT, Side.RIGHT)

#: (user id, side) -> the id of that user's hand on that side
HandIds = Callable[[int, Side], int]


def nuitrack_id(user: int, side: Side) -> int:
    return NUITRACK_IDS[side]


def renamed_gesture(g: Gesture, ids: HandIds) -> Gesture:
    """The gesture, naming its hand by its side's id (a gesture of no side keeps its hand's id)."""
    return replace(g, hand_id=ids(g.user_id, g.side)) if g.side in SIDES else g


def renamed_hand(h: Hand, ids: HandIds) -> Hand:
    return replace(h, id=ids(h.user_id, h.side)) if h.side in SIDES else h
