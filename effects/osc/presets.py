"""Templates, for patches that expect addresses of their own (`[[effects.messages]]` tables with
`{field}` placeholders), and what the bridge presets share (osceleton.py, synapse.py): the side a
hand is reported as, and positions as a mirror shows them.
"""
from __future__ import annotations

import re
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, model_validator

from effects.osc.coords import Projector
from effects.osc.schema import Scheme
from host import Frame, Gesture, Hand, Side, Vec3
from host.osc import Arg, Message, placeholders, typed

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


def performer_view(position: Vec3, frame: Frame) -> Vec3:
    """A position as the bridges' mirror view has it, +x towards the performer's right: ours when
    the depth image is mirrored (the default, and frames without an image), else x flipped."""
    if frame.depth is None or frame.depth.mirrored:
        return position
    return (-position[0], position[1], position[2])


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
