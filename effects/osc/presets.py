"""Compatibility presets, so patches written for older Kinect-to-OSC bridges keep working,
and templates, for patches that expect addresses of their own.

- OSCeleton (Sensebloom): `/joint s i f f f` and the user messages.
- Synapse (Ryan Challinor): `/righthand_pos_world f f f` and friends, gesture words per joint.
- templates: `[[effects.messages]]` tables with `{field}` placeholders.
"""
from __future__ import annotations

import re
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, model_validator

from effects.osc.coords import Projector
from effects.osc.schema import Scheme
from host import Frame, Gesture, Hand, Side
from host.osc import Arg, Message, placeholders, typed

OSCELETON_TEXT = """\
OSCeleton preset (scheme = "osceleton"; default destination 127.0.0.1:7110)

  /new_user   i            user         a user's first hand appears
  /new_skel   i            user         (sent with /new_user: joints follow)
  /joint      s i f f f    joint, user, x, y, z        per hand, per frame
  /lost_user  i            user         the user's last hand is gone

joint  r_hand | l_hand (a hand of unknown side takes the user's free side)
x      (X + 1280) / 2560: 0..1 over -1.28..1.28 m, growing towards the image's right
y      (960 - Y) / 1920:  0..1 over 0.96..-0.96 m, growing downwards
z      Z / 1280:          0..7.8 over 0..10 m (OSCeleton's Z * 7.8125 / 10000)
OSCeleton had no gestures: add templates (messages) to send them.
"""

SYNAPSE_TEXT = """\
Synapse preset (scheme = "synapse"; default destination 127.0.0.1:12345)

  /tracking_skeleton     i        1 when hands appear, 0 when they are all gone
  /righthand_pos_world   f f f    x, y, z millimetres (camera: x right, y up, z away)
  /righthand_pos_screen  f f f    u, v pixels in a 640x480 depth image, z millimetres
  /lefthand_pos_world    f f f
  /lefthand_pos_screen   f f f
  /righthand             s        a gesture word, when a gesture completes
  /lefthand              s

words  left, right, up, down (swipes, from the performer's point of view),
       forward (click / push), and, beyond Synapse's own words, wave, hand_raise
One user (the lowest user id); a hand of unknown side takes the free side. Synapse's
_pos_body needs the torso, which hand trackers do not report: it is not sent. No
keep-alive (/..._trackjointpos) is needed: positions are always sent.
"""

TEMPLATE_TEXT = """\
Templates (option messages; with scheme = "custom" they are all that is sent)

  [[effects.messages]]
  on = "hand"                      # "frame" | "hand" | "gesture"
  address = "/{side}/xyz"          # {field} placeholders, formatted with str.format
  args = ["{x}", "{y}", "{z}", 1]  # "{field}" alone keeps the field's type

frame    prefix, seq, t, hands, capture_time
hand     prefix, seq, t, id, user, side, state, tracking, x, y, z, x_mm, y_mm, z_mm,
         confidence (also for a hand gone since the last bundle: state absent)
gesture  prefix, name, native, state, complete, side, hand, t, x, y, z, x_mm, y_mm,
         z_mm, confidence

Types: int -> i, float -> f, text -> s, true / false -> T / F, capture_time -> d
(wall-clock seconds). With pd_safe = true (the default) T / F become i 1 / 0, d and
64-bit h become f or i, nil becomes the symbol nil: Pd 0.53's oscparse rejects T F N h d.
Frame and hand templates go into the frame's bundle; each gesture template is its own
datagram. x y z follow the option space; x_mm y_mm z_mm are always millimetres.
"""


def sided(hands: list[Hand]) -> list[tuple[Hand, Side]]:
    """Each hand with the side it is reported as: a hand of unknown side takes its user's free
    side (right first), since these formats only know a left and a right hand per user."""
    taken = {(h.user_id, h.side) for h in hands if h.side is not Side.UNKNOWN}
    out = []
    for hand in hands:
        side = hand.side
        if side is Side.UNKNOWN:
            side = next((s for s in (Side.RIGHT, Side.LEFT) if (hand.user_id, s) not in taken), None)
            if side is None:
                continue
            taken.add((hand.user_id, side))
        out.append((hand, side))
    return out


class OSCeletonScheme(Scheme):
    JOINTS = {Side.RIGHT: "r_hand", Side.LEFT: "l_hand"}

    def __init__(self, prefix: str = "") -> None:
        self.prefix = prefix
        self._users: set[int] = set()

    def frame(self, frame: Frame, hands: list[Hand], gone: list[Hand], to: Projector) -> list[Message]:
        p = self.prefix
        users = {h.user_id for h in hands}
        messages = []
        for user in sorted(users - self._users):
            messages += [Message(f"{p}/new_user", (("i", user),)), Message(f"{p}/new_skel", (("i", user),))]
        for hand, side in sided(hands):
            x, y, z = hand.position
            messages.append(Message(f"{p}/joint", (("s", self.JOINTS[side]), ("i", hand.user_id),
                                                   ("f", (x + 1280) / 2560), ("f", (960 - y) / 1920),
                                                   ("f", z / 1280))))
        messages += [Message(f"{p}/lost_user", (("i", user),)) for user in sorted(self._users - users)]
        self._users = users
        return messages


class SynapseScheme(Scheme):
    JOINTS = {Side.RIGHT: "righthand", Side.LEFT: "lefthand"}
    WORDS = {"swipe_left": "left", "swipe_right": "right", "swipe_up": "up", "swipe_down": "down",
             "click": "forward", "wave": "wave", "hand_raise": "hand_raise"}
    SCREEN = (640, 480)

    def __init__(self, prefix: str = "") -> None:
        self.prefix = prefix
        self._tracking = False
        self._joint_of: dict[int, str] = {}  # hand id -> joint, in the last frame

    def frame(self, frame: Frame, hands: list[Hand], gone: list[Hand], to: Projector) -> list[Message]:
        p = self.prefix
        if hands:
            user = min(h.user_id for h in hands)
            hands = [h for h in hands if h.user_id == user]
        messages = []
        if bool(hands) != self._tracking:
            self._tracking = bool(hands)
            messages.append(Message(f"{p}/tracking_skeleton", (("i", int(self._tracking)),)))
        screen = None
        if to.depth is not None:
            screen = to.depth.intrinsics.scaled(self.SCREEN[0] / to.depth.width, self.SCREEN[1] / to.depth.height)
        pairs = sided(hands)
        self._joint_of = {hand.id: self.JOINTS[side] for hand, side in pairs}
        for hand, side in pairs:
            joint = self.JOINTS[side]
            messages.append(Message(f"{p}/{joint}_pos_world", tuple(("f", c) for c in hand.position)))
            if screen is not None:
                x, y, z = hand.position
                u, v, _ = screen.world_to_depth(x, y, max(z, 1.0))
                messages.append(Message(f"{p}/{joint}_pos_screen", (("f", u), ("f", v), ("f", z))))
        return messages

    def gesture(self, gesture: Gesture, to: Projector) -> list[Message]:
        if gesture.state.value != "complete":
            return []  # Synapse reports hits, not motions under way
        joint = self.JOINTS.get(gesture.side) or self._joint_of.get(gesture.hand_id, "righthand")
        return [Message(f"{self.prefix}/{joint}", (("s", self.WORDS[gesture.name]),))]


FIELDS = {
    "frame": ("prefix", "seq", "t", "hands", "capture_time"),
    "hand": ("prefix", "seq", "t", "id", "user", "side", "state", "tracking", "x", "y", "z",
             "x_mm", "y_mm", "z_mm", "confidence"),
    "gesture": ("prefix", "name", "native", "state", "complete", "side", "hand", "t", "x", "y", "z",
                "x_mm", "y_mm", "z_mm", "confidence"),
}
_ALONE = re.compile(r"^\{(\w+)\}$")


class Template(BaseModel):
    """One custom message: sent per frame, per hand (in the frame's bundle) or per gesture."""

    model_config = ConfigDict(extra="forbid")
    on: Literal["frame", "hand", "gesture"]
    address: str
    args: list[str | bool | int | float] = []

    @model_validator(mode="after")
    def _check(self) -> "Template":
        known = FIELDS[self.on]
        texts = [self.address] + [a for a in self.args if isinstance(a, str)]
        for name in (n for text in texts for n in placeholders(text)):
            if name not in known:
                raise ValueError(f"unknown field {{{name}}} for on = {self.on!r}; expected one of {', '.join(known)}")
        if not (self.address.startswith("/") or self.address.startswith("{prefix}")):
            raise ValueError(f"address must start with / (or {{prefix}}), got {self.address!r}")
        return self

    def render(self, fields: dict[str, Arg]) -> Message:
        values = {k: v for k, (_, v) in fields.items()}
        return Message(self.address.format(**values), tuple(self._arg(a, fields, values) for a in self.args))

    @staticmethod
    def _arg(arg: Any, fields: dict[str, Arg], values: dict[str, Any]) -> Arg:
        if not isinstance(arg, str):
            return typed(arg)
        alone = _ALONE.match(arg)
        return fields[alone.group(1)] if alone else ("s", arg.format(**values))


class TemplateScheme(Scheme):
    """The `messages` option: the artist's own addresses, filled from our hands and gestures."""

    def __init__(self, templates: list[Template], prefix: str = "") -> None:
        self.prefix = prefix
        self.on = {kind: [t for t in templates if t.on == kind] for kind in FIELDS}

    def frame(self, frame: Frame, hands: list[Hand], gone: list[Hand], to: Projector) -> list[Message]:
        base = {"prefix": ("s", self.prefix), "seq": typed(frame.seq), "t": ("f", frame.timestamp)}
        messages = [t.render({**base, "hands": typed(len(hands)), "capture_time": ("d", frame.capture_time)})
                    for t in self.on["frame"]]
        for hand, state in [(h, h.state.value) for h in hands] + [(h, "absent") for h in gone]:
            fields = {**base, "id": typed(hand.id), "user": typed(hand.user_id), "side": ("s", hand.side.value),
                      "state": ("s", state), "tracking": typed(state != "absent"),
                      "confidence": ("f", hand.confidence if state != "absent" else 0.0),
                      **_position(hand.position, to)}
            messages += [t.render(fields) for t in self.on["hand"]]
        return messages

    def gesture(self, gesture: Gesture, to: Projector) -> list[Message]:
        fields = {"prefix": ("s", self.prefix), "name": ("s", gesture.name), "native": ("s", gesture.type.value),
                  "state": ("s", gesture.state.value), "complete": typed(gesture.state.value == "complete"),
                  "side": ("s", gesture.side.value), "hand": typed(gesture.hand_id), "t": ("f", gesture.timestamp),
                  "confidence": ("f", gesture.confidence), **_position(gesture.position, to)}
        return [t.render(fields) for t in self.on["gesture"]]


def _position(position, to: Projector) -> dict[str, Arg]:
    x, y, z = to(position)
    return {"x": ("f", x), "y": ("f", y), "z": ("f", z),
            "x_mm": ("f", position[0]), "y_mm": ("f", position[1]), "z_mm": ("f", position[2])}
