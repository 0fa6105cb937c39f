"""OSC 1.0 on the wire: typed arguments, Pure Data type safety, messages and bundles as bytes;
and the `{field}` placeholders of OSC message templates (a public host module: the `osc` effect
sends with it, the `osc-in` backend and `issv osc-replay` use the same encoding and templates).

Every argument carries its OSC type tag explicitly, so what goes out is exactly what the
address scheme documents. Encoding is done here with `struct` rather than python-osc's
builders: it runs on the show loop once per frame, and python-osc's builders cost ~10x more
(about 0.1 ms per bundle), time that sits between capture and the sound. python-osc decodes
what this encodes in the tests, next to liblo's oscdump and Pure Data's oscparse.
"""
from __future__ import annotations

import numbers
import string
import struct
from dataclasses import dataclass
from typing import Any

Arg = tuple[str, Any]  # (OSC type tag, value)

INT32 = range(-2**31, 2**31)
PD_TYPES = frozenset("ifs")  # what Pd 0.53's oscparse accepts (it rejects T, F, N, h and d)


@dataclass(frozen=True)
class Message:
    """One OSC message before encoding: an address and typed arguments."""

    address: str
    args: tuple[Arg, ...] = ()

    @property
    def types(self) -> str:
        return "".join(tag for tag, _ in self.args)


def typed(value: Any) -> Arg:
    """The OSC type a Python value naturally has (bool before int: bool is an int in Python)."""
    if value is None:
        return ("N", None)
    if isinstance(value, bool):
        return ("T", True) if value else ("F", False)
    if isinstance(value, numbers.Integral):
        return ("i", int(value)) if int(value) in INT32 else ("h", int(value))
    if isinstance(value, numbers.Real):
        return ("f", float(value))
    return ("s", str(value))


def pd_safe(arg: Arg) -> Arg:
    """The same value in a type Pd's oscparse accepts: true/false -> 1/0, nil -> the symbol
    `nil`, 64-bit integers -> i when they fit in 32 bits else f, doubles -> f."""
    tag, value = arg
    if tag in PD_TYPES:
        return arg
    if tag in "TF":
        return ("i", 1 if tag == "T" else 0)
    if tag == "N":
        return ("s", "nil")
    if tag == "h":
        return ("i", value) if value in INT32 else ("f", float(value))
    if tag == "d":
        return ("f", float(value))
    raise ValueError(f"OSC type {tag!r} has no Pure Data equivalent")


def safe_for_pd(message: Message) -> Message:
    if all(tag in PD_TYPES for tag, _ in message.args):
        return message
    return Message(message.address, tuple(pd_safe(a) for a in message.args))


def _string(text: str) -> bytes:
    data = text.encode("utf-8") + b"\0"
    return data + b"\0" * (-len(data) % 4)


_PACK = {"i": struct.Struct(">i").pack, "f": struct.Struct(">f").pack, "h": struct.Struct(">q").pack,
         "d": struct.Struct(">d").pack, "s": _string}
_BUNDLE_HEAD = _string("#bundle") + struct.pack(">Q", 1)  # time tag 1: immediately
_SIZE = struct.Struct(">i").pack


def _encode(message: Message) -> bytes:
    parts = [_string(message.address), _string("," + message.types)]
    parts += [_PACK[tag](value) for tag, value in message.args if tag not in "TFN"]
    return b"".join(parts)


def encode(message: Message, pd: bool) -> bytes:
    """One message as a datagram."""
    return _encode(safe_for_pd(message) if pd else message)


def encode_bundle(messages: list[Message], pd: bool, time_tag: int = 1) -> bytes:
    """Messages as one bundle: one datagram, one instant. `time_tag`: NTP 32.32 fixed point, or 1
    (the default) for `immediately`."""
    parts = [_BUNDLE_HEAD if time_tag == 1 else _string("#bundle") + struct.pack(">Q", time_tag)]
    for message in messages:
        data = encode(message, pd)
        parts += [_SIZE(len(data)), data]
    return b"".join(parts)


def placeholders(text: str) -> list[str]:
    """The {field} names in a template text (str.format syntax)."""
    try:
        return [name for _, name, _, _ in string.Formatter().parse(text) if name is not None]
    except ValueError as error:
        raise ValueError(f"{text!r}: {error} (write {{{{ and }}}} for literal braces)") from None
