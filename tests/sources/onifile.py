"""A second reader for OpenNI 1.x `.oni` recordings, written for the tests from the file layout
(OpenNI2's Source/Drivers/OniFile: DataRecords.h, XnStreamCompression.cpp), sharing nothing with
the `oni` source's path (OpenNI2's C++ player and codec). It reads what the tests need: the depth
node's properties and each frame's stored values, decoded from the "16zT" codec (PrimeSense's
16-bit delta code over an embedded table of the values used), the codec of the real take.

Only the 32-bit record header of files written before OpenNI 1.0.1 is read (the real take in
tests/data is one); anything else fails with what it found.
"""
from __future__ import annotations

import struct
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

RECORD_HEADER = struct.Struct("<4sIIIII")  # magic, type, node id, fields size, payload size, undo position
INT, REAL, STRING, GENERAL, NODE_ADDED, NEW_DATA, END = 0x03, 0x04, 0x05, 0x06, 0x0D, 0x0A, 0x0B


@dataclass
class OniFrame:
    number: int
    timestamp_us: int
    payload: bytes


@dataclass
class OniTake:
    codec: str
    properties: dict[str, object] = field(default_factory=dict)
    frames: list[OniFrame] = field(default_factory=list)

    @property
    def size(self) -> tuple[int, int]:
        width, height, _fps = struct.unpack("<III", self.properties["xnMapOutputMode"])
        return width, height

    def depth(self, index: int) -> np.ndarray:
        """Frame `index` as stored: 16-bit values, row by row."""
        width, height = self.size
        payload = self.frames[index].payload
        if self.codec != "16zT":
            raise ValueError(f"codec {self.codec!r} is not read by this test reader")
        values = np.array(decode_16z_table(payload), np.uint16)
        assert values.size == width * height, (values.size, width, height)
        return values.reshape(height, width)


def _name(fields: bytes, at: int) -> tuple[str, int]:
    (length,) = struct.unpack_from("<I", fields, at)  # counts the terminating NUL
    return fields[at + 4: at + 4 + length - 1].decode(), at + 4 + length


def read_oni(path: Path) -> OniTake:
    data = Path(path).read_bytes()
    magic, version = data[:4], struct.unpack_from("<BBHI", data, 4)
    if magic != b"NI10" or version >= (1, 0, 1, 0):
        raise ValueError(f"{path}: magic {magic!r}, version {version}: not an OpenNI 1.0.0.x recording")
    take, pos = None, 24  # header: magic, version, max timestamp (u64), max node id (u32)
    while pos < len(data):
        magic, kind, _node, fields_size, payload_size, _undo = RECORD_HEADER.unpack_from(data, pos)
        if magic != b"NIR\0":
            raise ValueError(f"{path}: no record at byte {pos}")
        fields = data[pos + RECORD_HEADER.size: pos + fields_size]
        if kind == NODE_ADDED:
            _node_name, at = _name(fields, 0)
            _node_type, codec = struct.unpack_from("<I4s", fields, at)
            take = OniTake(codec.decode().rstrip("\0"))
        elif kind in (INT, REAL, STRING, GENERAL):
            name, at = _name(fields, 0)
            (size,) = struct.unpack_from("<I", fields, at)
            value = fields[at + 4: at + 4 + size]
            take.properties[name] = (struct.unpack("<Q", value)[0] if kind == INT else
                                     struct.unpack("<d", value)[0] if kind == REAL else value)
        elif kind == NEW_DATA:
            timestamp, number = struct.unpack_from("<QI", fields)
            start = pos + fields_size
            take.frames.append(OniFrame(number, timestamp, data[start: start + payload_size]))
        elif kind == END:
            break
        pos += fields_size + payload_size
    return take


def decode_16z_table(buf: bytes) -> list[int]:
    """PrimeSense's 16z code: nibble deltas (-6..+7 around 6), one-byte deltas (0x80 | d + 64),
    big-endian full values, 0xE0 + n = 2n repeats; here over indices into an embedded table."""
    (entries,) = struct.unpack_from("<H", buf, 0)
    table = struct.unpack_from(f"<{entries}H", buf, 2)
    pos = 2 + 2 * entries
    (last,) = struct.unpack_from("<H", buf, pos)
    pos += 2
    out = [table[last]]
    end = len(buf)

    def wide(at: int) -> tuple[int, int]:  # after a 0xF escape: a one-byte delta or a full value
        byte = buf[at]
        if byte & 0x80:
            return (last - (byte - 192)) & 0xFFFF, at + 1
        return (byte << 8) | buf[at + 1], at + 2

    while pos < end:
        byte = buf[pos]
        if byte < 0xE0:
            last = (last - ((byte >> 4) - 6)) & 0xFFFF
            out.append(table[last])
            low = byte & 0x0F
            if low == 0x0F:
                last, pos = wide(pos + 1)
                out.append(table[last])
            else:
                if low != 0x0D:  # 0xD pads an odd count
                    last = (last - (low - 6)) & 0xFFFF
                    out.append(table[last])
                pos += 1
        elif byte == 0xFF:
            last, pos = wide(pos + 1)
            out.append(table[last])
        else:
            out.extend([table[last]] * (2 * (byte - 0xE0)))
            pos += 1
    return out
