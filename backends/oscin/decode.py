"""OSC 1.0 datagrams to (time tag, address, arguments), bundles flattened in order.

Written here rather than taken from python-osc: its parser turns every bundle time tag into
"now" (1.10), and the receiver needs the tag to tell a sender's sample times from arrival times.
It reads every OSC 1.0 type and the common 1.1 extras (h, d, T, F, N, I, c, m, t).
"""
from __future__ import annotations

import struct
from typing import Any

IMMEDIATELY = 1
NTP_UNIX_OFFSET = 2208988800  # seconds from 1900-01-01 (NTP) to 1970-01-01 (Unix)
DAY = 86400

_I32, _F32, _I64, _F64, _U64 = (struct.Struct(f">{c}") for c in "ifqdQ")


class OscError(ValueError):
    """Bytes that are not an OSC packet."""


def _string(data: bytes, pos: int) -> tuple[str, int]:
    end = data.find(b"\0", pos)
    if end < 0:
        raise OscError("unterminated string")
    try:
        text = data[pos:end].decode("utf-8")
    except UnicodeDecodeError as error:
        raise OscError(f"string is not UTF-8 ({error.reason})") from None
    return text, end + 1 + (-(end + 1 - pos) % 4)


def _message(data: bytes) -> tuple[str, list[Any]]:
    address, pos = _string(data, 0)
    if not address.startswith("/"):
        raise OscError(f"address {address!r} does not start with /")
    if pos >= len(data):
        return address, []  # OSC 1.0 allows a message without a type tag string
    tags, pos = _string(data, pos)
    if not tags.startswith(","):
        raise OscError(f"type tags {tags!r} do not start with ,")
    args: list[Any] = []
    try:
        for tag in tags[1:]:
            if tag == "i":
                args.append(_I32.unpack_from(data, pos)[0]); pos += 4
            elif tag == "f":
                args.append(_F32.unpack_from(data, pos)[0]); pos += 4
            elif tag in "sS":
                text, pos = _string(data, pos); args.append(text)
            elif tag == "h":
                args.append(_I64.unpack_from(data, pos)[0]); pos += 8
            elif tag == "d":
                args.append(_F64.unpack_from(data, pos)[0]); pos += 8
            elif tag == "t":
                args.append(_U64.unpack_from(data, pos)[0]); pos += 8
            elif tag in "cmr":
                args.append(_I32.unpack_from(data, pos)[0]); pos += 4
            elif tag == "b":
                size = _I32.unpack_from(data, pos)[0]; pos += 4
                args.append(bytes(data[pos:pos + size])); pos += size + (-size % 4)
            elif tag in "TFNI":
                args.append({"T": True, "F": False, "N": None, "I": float("inf")}[tag])
            else:
                raise OscError(f"unknown type tag {tag!r}")
    except struct.error:
        raise OscError(f"{address}: arguments shorter than their type tags {tags}") from None
    return address, args


def decode(data: bytes, time_tag: int = IMMEDIATELY) -> list[tuple[int, str, list[Any]]]:
    """Every message of a packet with the time tag of its innermost bundle (IMMEDIATELY if none)."""
    if not data.startswith(b"#bundle\0"):
        return [(time_tag, *_message(data))]
    if len(data) < 16:
        raise OscError("bundle shorter than its header")
    tag = _U64.unpack_from(data, 8)[0]
    out, pos = [], 16
    while pos < len(data):
        if pos + 4 > len(data):
            raise OscError("bundle element without its size")
        size = _I32.unpack_from(data, pos)[0]
        pos += 4
        if size < 0 or pos + size > len(data) or size % 4:
            raise OscError(f"bundle element size {size} does not fit the packet")
        out += decode(data[pos:pos + size], tag)
        pos += size
    return out


def time_tag(unix: float) -> int:
    """Unix seconds as an NTP time tag."""
    seconds = unix + NTP_UNIX_OFFSET
    whole = int(seconds)
    return (whole << 32) | int((seconds - whole) * 2**32)


def midnight(tag: int) -> int:
    """The time tag of midnight (UTC) of the day a tag falls in: the origin of a stream's clock."""
    return (tag >> 32) // DAY * DAY << 32


def stamp(origin: int, seconds: float) -> int:
    """The time tag `seconds` after `origin` (a midnight), rounded to the tag's 2^-32 s. With
    integers, not Unix seconds as floats (those keep only half a microsecond today)."""
    return origin + round(seconds * 2**32)


def seconds_since(origin: int, tag: int) -> float:
    """`stamp`'s inverse, to the nanosecond: a sender's own times with up to nine decimals (a
    tracker's millisecond clock, a file's 0.1 ms) come back as the very same floats, so a
    recogniser that compares sample intervals exactly sees the sender's clock, not the wire's."""
    return round((tag - origin) / 2**32, 9)
