"""The wire format of `issv serve`: what one message is, byte for byte (documented in README.md).

Every message starts with the same 32-byte header, little-endian:

    magic  b"ISSV"   4 bytes
    version u8       (3; versions 1, without users, and 2, without user labels, are still read)
    kind    u8       DEPTH 1, HANDS 2, GESTURE 3, HEARTBEAT 4, BYE 5
    flags   u16      bit 0 (LABELS): a DEPTH message that carries its user label image; else 0
    session u64      random per publisher run: a new value means the publisher restarted
    seq     u64      per stream (depth, hands, gestures), from 1, no gaps at the sender
    capture f64      wall-clock time (time.time()) when the sensor captured the frame

then the body. HANDS, GESTURE, HEARTBEAT and BYE bodies are compact JSON (small, readable from any
language). Version 2 added the users: a HANDS body's `users` (id, state, centre of mass `com`,
`joints` {name: [x, y, z, confidence]}), a ninth value per hand row (`extended`: true, false or
null) and a GESTURE body's `user`; version 1 messages decode with no users, `extended` null and
user 1. A DEPTH body is a fixed binary block followed by the compressed image:

    frame_seq u64, frame_id u64, timestamp f64, width u16, height u16, codec u8, mirrored u8,
    2 pad bytes, fx f64, fy f64, cx f64, cy f64     (the intrinsics of the image as sent, so a
    cropped or downscaled image still converts between millimetres and pixels correctly)

With the LABELS flag (version 3), the block is followed by the user label image of the same
frame, at the same size as the depth image as sent (cropped and downscaled alike): `u8 labels
codec (1 = zstd), 3 pad bytes, u32 n`, then n bytes: the row-major uint8 labels (0 nobody, else
the user's id, as Frame.user_labels) compressed by zstd. The compressed depth image comes last,
as without labels. Labels ride in the depth message because depth is newest-wins (one queued
message per subscriber): a message of their own would push out the depth image of their frame.
Decoding never trusts the bytes: any problem raises `WireError` whose `kind` names what was wrong
(the subscriber counts problems per kind).
"""
from __future__ import annotations

import importlib.util
import json
import math
import os
import struct
import threading
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Callable, TypeVar

import numpy as np
import zstandard

from host import DepthFrame, Gesture, GestureState, GestureType, Hand, HandState, Intrinsics, Joint, Side, User
from host import compression

MAGIC = b"ISSV"
VERSION = 3
READS = (1, 2, 3)  # versions decoded
LABELS = 1  # header flag of a DEPTH message carrying user labels
DEPTH, HANDS, GESTURE, HEARTBEAT, BYE = 1, 2, 3, 4, 5
STREAMS = {DEPTH: "depth", HANDS: "hands", GESTURE: "gestures"}
HEADER = struct.Struct("<4sBBHQQd")
DEPTH_BODY = struct.Struct("<QQdHHBB2x4d")
LABELS_BLOCK = struct.Struct("<B3xI")
LABELS_ZSTD = 1
MAX_PIXELS = 4096 * 4096  # refuse to allocate more than this for one depth image
MAX_JSON = 1 << 20
MAX_USERS, MAX_JOINTS, MAX_NAME = 16, 32, 32
T = TypeVar("T")


class WireError(ValueError):
    """A message that cannot be decoded; `kind` is a short name for what was wrong."""

    def __init__(self, kind: str, detail: str) -> None:
        super().__init__(f"{kind}: {detail}")
        self.kind = kind


@dataclass(frozen=True)
class Header:
    kind: int
    session: int
    seq: int
    capture_time: float


@dataclass(frozen=True)
class DepthMsg:
    """One depth image and, when the publisher's backend knows them, its user labels."""

    header: Header
    frame_seq: int
    depth: DepthFrame
    labels: np.ndarray | None = None  # uint8 (H, W) like depth: 0 nobody, else the user's id


@dataclass(frozen=True)
class LabelsMsg:
    """A user label image that travels apart from its depth image (ROS's user_labels topic; ZeroMQ
    carries labels inside the depth message): it belongs to the depth image captured at the same
    `header.capture_time` in the same session."""

    header: Header
    labels: np.ndarray


@dataclass(frozen=True)
class HandsMsg:
    """The hands of one publisher frame; `depth` says whether a depth message was sent for it."""

    header: Header
    frame_seq: int
    timestamp: float
    backend: str
    hands: tuple[Hand, ...]
    depth: bool
    users: tuple[User, ...] = ()


@dataclass(frozen=True)
class GestureMsg:
    header: Header
    frame_seq: int
    gesture: Gesture


@dataclass(frozen=True)
class StatusMsg:
    """HEARTBEAT or BYE: the last sequence number sent on each stream (for tail loss)."""

    header: Header
    last: dict[str, int]
    backend: str
    depth_skipped: int


Message = DepthMsg | HandsMsg | GestureMsg | StatusMsg | LabelsMsg


# -- lossless depth codecs ---------------------------------------------------------------------
# Measured by bench/network.py (its `codecs` table) on Kinect-like 640x480 frames and on the real
# UTD-MHAD clips. Kinect v1 millimetres come from an 11-bit disparity, so a row holds few distinct
# values and plain zstd level 1 finds them: it compressed best on every set we tried (3.4-5x on
# Kinect-like frames, ~50x on background-removed clips) at 1.5-4 ms per frame. A row delta turns
# quantisation steps into many distinct values and made zstd worse (2.2-3.6x); lz4 is fast but
# halves the ratio; blosc2's shuffle + lz4/zstd filters did no better (1.5-3.5x at 0.8-2 ms). The
# default is plain zstd in bands (below); the alternatives stay selectable (`issv serve --codec`)
# and measured.


def _zstd_in(data: bytes) -> bytes:
    return compression.compressor().compress(data)


def _delta(data: np.ndarray) -> np.ndarray:
    out = data.copy()
    out[:, 1:] -= data[:, :-1]  # uint16 arithmetic wraps: exactly invertible by a cumulative sum
    return out


def _undelta(delta: np.ndarray) -> np.ndarray:
    # A wide accumulator is faster than uint16 and equal modulo 2**16 (rows are < 2**47 long).
    return np.cumsum(delta.view(np.int16), axis=1).astype(np.uint16)


def _shuffle(data: np.ndarray) -> bytes:
    return data.view(np.uint8).reshape(-1, 2).T.tobytes()


def _unshuffle(raw: bytes, shape: tuple[int, int]) -> np.ndarray:
    planes = np.frombuffer(raw, np.uint8).reshape(2, -1)
    out = np.empty((planes.shape[1], 2), np.uint8)
    out[:, 0], out[:, 1] = planes
    return out.view(np.uint16).reshape(shape)


def _zstd_out(payload: bytes, size: int) -> bytes:
    try:
        out = compression.decompressor().decompress(payload, max_output_size=size)
    except zstandard.ZstdError as error:
        raise WireError("bad-depth", f"zstd: {error}") from None
    if len(out) != size:
        raise WireError("bad-depth", f"decompressed {len(out)} bytes, expected {size}")
    return out


def _lz4_encode(data: bytes) -> bytes:
    import lz4.frame
    return lz4.frame.compress(data)


def _lz4_decode(payload: bytes, size: int) -> bytes:
    import lz4.frame
    try:
        with lz4.frame.LZ4FrameDecompressor() as d:
            out = d.decompress(payload, max_length=size)
    except RuntimeError as error:
        raise WireError("bad-depth", f"lz4: {error}") from None
    if len(out) != size:
        raise WireError("bad-depth", f"decompressed {len(out)} bytes, expected {size}")
    return out


def _raw_decode(payload: bytes, size: int) -> bytes:
    if len(payload) != size:
        raise WireError("bad-depth", f"{len(payload)} raw bytes, expected {size}")
    return payload


Pause = Callable[[], None]


@dataclass(frozen=True)
class Codec:
    id: int
    name: str
    encode: Callable[[np.ndarray, Pause | None], bytes]  # (image, called between chunks of work)
    decode: Callable[[bytes, tuple[int, int]], np.ndarray]


def _bytes_codec(cid: int, name: str, pre: Callable[[np.ndarray], bytes], post: Callable[[bytes, tuple], np.ndarray],
                 squeeze: Callable[[bytes], bytes], unsqueeze: Callable[[bytes, int], bytes]) -> Codec:
    return Codec(cid, name, lambda a, pause=None: squeeze(pre(a)),
                 lambda p, shape: post(unsqueeze(p, shape[0] * shape[1] * 2), shape))


def _plain(a: np.ndarray) -> bytes:
    return a.tobytes()


def _unplain(raw: bytes, shape: tuple[int, int]) -> np.ndarray:
    return np.frombuffer(raw, np.uint16).reshape(shape)


def _delta_shuffle(a: np.ndarray) -> bytes:
    return _shuffle(_delta(a))


def _undelta_shuffle(raw: bytes, shape: tuple[int, int]) -> np.ndarray:
    return _undelta(_unshuffle(raw, shape))


# Banded zstd (the default): the image in bands of rows, each its own zstd frame, compressed and
# decompressed two bands at a time where the machine has two cores (zstd releases the GIL). A
# 640x480 image takes ~2 ms in one piece; in bands on two threads about half, and the compressor
# steps aside between bands (`pause`), so on a busy machine the threads carrying hands and gestures
# are never held up for a whole image (bench, publisher and subscriber on one 2-core machine:
# event p99 3.5-4 ms with one-piece zstd, 1.7 ms in bands; depth at 100 Mbit/s 1.33 -> 1.26 x the
# link's carry time). The body is `u16 n, n x u32 band sizes, bands`; band i holds rows
# [i * r, (i + 1) * r) with r = ceil(height / n). Bands of 64 K pixels (five for 640x480) cost
# under 1 % of the ratio; 32 K-pixel bands cost 3 % and a millisecond of depth latency.
BAND_PIXELS = 1 << 16
_BANDS = struct.Struct("<H")
_TWO_CORES = (os.cpu_count() or 1) >= 2
_band_pool: ThreadPoolExecutor | None = None
_band_pool_lock = threading.Lock()


def _each_band(work: Callable[[int], T], count: int) -> list[T]:
    """work(0), ..., work(count - 1), in order; on two threads where there are two cores."""
    global _band_pool
    if count < 2 or not _TWO_CORES:
        return [work(i) for i in range(count)]
    with _band_pool_lock:
        if _band_pool is None:
            _band_pool = ThreadPoolExecutor(2, thread_name_prefix="issv-zstd-band")
    return list(_band_pool.map(work, range(count)))


def _band_rows(height: int, width: int) -> int:
    """Rows per band: bands of about BAND_PIXELS, as even as ceil(height / n) makes them."""
    n = -(-height // max(1, min(height, BAND_PIXELS // max(1, width))))
    return -(-height // n)


def _banded_encode(a: np.ndarray, pause: Pause | None = None) -> bytes:
    a = np.ascontiguousarray(a)
    rows = _band_rows(*a.shape)

    def band(i: int) -> bytes:
        out = _zstd_in(a[i * rows:(i + 1) * rows])
        if pause is not None:
            pause()
        return out

    bands = _each_band(band, -(-a.shape[0] // rows))
    return struct.pack(f"<H{len(bands)}I", len(bands), *map(len, bands)) + b"".join(bands)


def _banded_decode(payload: bytes, shape: tuple[int, int]) -> np.ndarray:
    height, width = shape
    view = memoryview(payload)
    if len(view) < _BANDS.size:
        raise WireError("bad-depth", "banded depth without its band count")
    (n,) = _BANDS.unpack_from(view)
    if not 0 < n <= height:
        raise WireError("bad-depth", f"{n} bands for {height} rows")
    table = struct.Struct(f"<{n}I")
    if len(view) < _BANDS.size + table.size:
        raise WireError("bad-depth", "banded depth shorter than its band table")
    sizes = table.unpack_from(view, _BANDS.size)
    if _BANDS.size + table.size + sum(sizes) != len(view):
        raise WireError("bad-depth", "band sizes do not add up to the message")
    rows = -(-height // n)
    starts = np.cumsum((_BANDS.size + table.size, *sizes))
    out = np.empty(shape, np.uint16)

    def band(i: int) -> None:
        rows_i = out[i * rows:(i + 1) * rows]
        raw = _zstd_out(view[starts[i]:starts[i + 1]], rows_i.nbytes)
        rows_i[...] = np.frombuffer(raw, np.uint16).reshape(rows_i.shape)

    _each_band(band, n)
    return out


CODECS: dict[str, Codec] = {c.name: c for c in (
    _bytes_codec(0, "raw", _plain, _unplain, lambda b: b, _raw_decode),
    _bytes_codec(1, "zstd", _plain, _unplain, _zstd_in, _zstd_out),
    _bytes_codec(2, "delta-shuffle-zstd", _delta_shuffle, _undelta_shuffle, _zstd_in, _zstd_out),
    _bytes_codec(4, "shuffle-zstd", _shuffle, _unshuffle, _zstd_in, _zstd_out),
    Codec(5, "banded-zstd", _banded_encode, _banded_decode),
)}
if importlib.util.find_spec("lz4") is not None:  # optional: measured when installed
    CODECS["delta-shuffle-lz4"] = _bytes_codec(3, "delta-shuffle-lz4", _delta_shuffle, _undelta_shuffle,
                                               _lz4_encode, _lz4_decode)
CODEC_BY_ID = {c.id: c for c in CODECS.values()}
DEFAULT_CODEC = "banded-zstd"


# -- encoding ----------------------------------------------------------------------------------
def header(kind: int, session: int, seq: int, capture_time: float, flags: int = 0) -> bytes:
    return HEADER.pack(MAGIC, VERSION, kind, flags, session, seq, capture_time)


def encode_labels(labels: np.ndarray) -> bytes:
    """The labels block: a 640x480 label image of two users is ~300 KB raw, a few KB in zstd
    (bench/network.py's `labels` table)."""
    payload = _zstd_in(np.ascontiguousarray(labels, np.uint8))
    return LABELS_BLOCK.pack(LABELS_ZSTD, len(payload)) + payload


def labels_size(msg: bytes) -> int:
    """Bytes of the labels block in an encoded DEPTH message (0 without labels)."""
    if not HEADER.unpack_from(msg)[3] & LABELS:
        return 0
    return LABELS_BLOCK.size + LABELS_BLOCK.unpack_from(msg, HEADER.size + DEPTH_BODY.size)[1]


def encode_depth(session: int, seq: int, capture_time: float, frame_seq: int, depth: DepthFrame,
                 codec: str = DEFAULT_CODEC, pause: Pause | None = None, labels: np.ndarray | None = None) -> bytes:
    c = CODECS[codec]
    i = depth.intrinsics
    body = DEPTH_BODY.pack(frame_seq, depth.frame_id % 2**64, depth.timestamp, depth.width, depth.height, c.id,
                           int(depth.mirrored), i.fx, i.fy, i.cx, i.cy)
    if labels is not None and labels.shape != depth.data.shape:
        raise ValueError(f"user labels of shape {labels.shape} for a depth image of shape {depth.data.shape}")
    block = b"" if labels is None else encode_labels(labels)
    return (header(DEPTH, session, seq, capture_time, LABELS if labels is not None else 0)
            + body + block + c.encode(depth.data, pause))


def _json(kind: int, session: int, seq: int, capture_time: float, body: dict) -> bytes:
    return header(kind, session, seq, capture_time) + json.dumps(body, separators=(",", ":")).encode()


def encode_hands(session: int, seq: int, capture_time: float, frame_seq: int, timestamp: float,
                 backend: str, hands: tuple[Hand, ...], depth: bool, users: tuple[User, ...] = ()) -> bytes:
    return _json(HANDS, session, seq, capture_time, {
        "frame": frame_seq, "t": timestamp, "backend": backend, "depth": depth,
        "hands": [[h.id, h.state.value, *h.position, h.side.value, h.user_id, h.confidence, h.extended]
                  for h in hands],
        "users": [{"id": u.id, "state": u.state.value,
                   "com": None if u.center_of_mass is None else list(u.center_of_mass),
                   "joints": {name: [*j.position, j.confidence] for name, j in u.joints.items()}} for u in users]})


def encode_gesture(session: int, seq: int, capture_time: float, frame_seq: int, g: Gesture) -> bytes:
    return _json(GESTURE, session, seq, capture_time, {
        "frame": frame_seq, "type": g.type.value, "state": g.state.value, "position": list(g.position),
        "hand": g.hand_id, "side": g.side.value, "confidence": g.confidence, "t": g.timestamp, "user": g.user_id,
        **({"name": g.label} if g.label else {}), **({"hands": list(g.hands)} if g.hands else {})})


def encode_status(kind: int, session: int, seq: int, last: dict[str, int], backend: str,
                  depth_skipped: int, now: float) -> bytes:
    return _json(kind, session, seq, now, {"last": last, "backend": backend, "depth_skipped": depth_skipped})


# -- decoding (never trusts the bytes) ---------------------------------------------------------
def decode(data: bytes) -> Message:
    if len(data) < HEADER.size:
        raise WireError("truncated", f"{len(data)} bytes, shorter than the {HEADER.size}-byte header")
    magic, version, kind, flags, session, seq, capture = HEADER.unpack_from(data)
    if magic != MAGIC:
        raise WireError("bad-magic", f"starts with {magic!r}, not {MAGIC!r}")
    if version not in READS:
        raise WireError("bad-version", f"version {version}, this issv reads "
                                         f"{', '.join(map(str, READS[:-1]))} and {READS[-1]}")
    if not math.isfinite(capture):
        raise WireError("bad-field", "capture time is not a finite number")
    h = Header(kind, session, seq, capture)
    body = memoryview(data)[HEADER.size:]
    if kind == DEPTH:
        return _decode_depth(h, body, bool(flags & LABELS) and version >= 3)
    if kind in (HANDS, GESTURE, HEARTBEAT, BYE):
        doc = _load_json(body)
        try:
            return _JSON_DECODERS[kind](h, doc)
        except (KeyError, TypeError, ValueError, IndexError, AttributeError) as error:
            raise WireError("bad-field", f"{type(error).__name__}: {error}") from None
    raise WireError("unknown-kind", f"message kind {kind}")


def _decode_depth(h: Header, body: memoryview, with_labels: bool) -> DepthMsg:
    if len(body) < DEPTH_BODY.size:
        raise WireError("truncated", f"depth body of {len(body)} bytes, shorter than {DEPTH_BODY.size}")
    frame_seq, frame_id, ts, w, hgt, codec_id, mirrored, fx, fy, cx, cy = DEPTH_BODY.unpack_from(body)
    codec = CODEC_BY_ID.get(codec_id)
    if codec is None:
        raise WireError("bad-depth", f"unknown codec {codec_id}")
    if not (0 < w * hgt <= MAX_PIXELS):
        raise WireError("bad-depth", f"image size {w}x{hgt}")
    if not all(math.isfinite(v) for v in (ts, fx, fy, cx, cy)) or fx <= 0 or fy <= 0:
        raise WireError("bad-depth", "timestamp or intrinsics are not usable numbers")
    start, labels = DEPTH_BODY.size, None
    if with_labels:
        labels, start = _decode_labels(body, start, (hgt, w))
    data = codec.decode(body[start:], (hgt, w))
    depth = DepthFrame(data, Intrinsics(fx, fy, cx, cy), frame_id=frame_id, timestamp=ts,
                       capture_time=h.capture_time, mirrored=bool(mirrored))
    return DepthMsg(h, frame_seq, depth, labels)


def _decode_labels(body: memoryview, start: int, shape: tuple[int, int]) -> tuple[np.ndarray, int]:
    """The labels block at `start`: (labels, where the depth image begins)."""
    if len(body) < start + LABELS_BLOCK.size:
        raise WireError("bad-labels", "a depth message flagged with labels is too short for them")
    codec, size = LABELS_BLOCK.unpack_from(body, start)
    if codec != LABELS_ZSTD:
        raise WireError("bad-labels", f"unknown labels codec {codec}")
    start += LABELS_BLOCK.size
    if len(body) < start + size:
        raise WireError("bad-labels", f"labels of {size} bytes in a message {len(body) - start} bytes shorter")
    try:
        raw = _zstd_out(body[start:start + size], shape[0] * shape[1])
    except WireError as error:
        raise WireError("bad-labels", str(error).partition(": ")[2]) from None
    return np.frombuffer(raw, np.uint8).reshape(shape), start + size


def _load_json(body: memoryview) -> dict:
    if len(body) > MAX_JSON:
        raise WireError("oversize", f"{len(body)} bytes of JSON")
    try:
        doc = json.loads(bytes(body))
    except (UnicodeDecodeError, ValueError, RecursionError) as error:
        raise WireError("bad-json", str(error)[:80]) from None
    if not isinstance(doc, dict):
        raise WireError("bad-json", f"expected an object, got {type(doc).__name__}")
    return doc


def _num(v: object) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise ValueError(f"expected a finite number, got {v!r}")
    return float(v)


def _int(v: object) -> int:
    if isinstance(v, bool) or not isinstance(v, int):
        raise ValueError(f"expected an integer, got {v!r}")
    return v


def _vec(v: object) -> tuple[float, float, float]:
    if not isinstance(v, list) or len(v) != 3:
        raise ValueError(f"expected [x, y, z], got {v!r}")
    return (_num(v[0]), _num(v[1]), _num(v[2]))


def _hand(row: object) -> Hand:
    if not isinstance(row, list) or len(row) not in (8, 9):
        raise ValueError(f"expected a hand row of 8 values (9 with extended), got {row!r}")
    extended = row[8] if len(row) == 9 else None
    if extended is not None and not isinstance(extended, bool):
        raise ValueError(f"extended must be true, false or null, got {extended!r}")
    return Hand(_int(row[0]), HandState(row[1]), _vec(row[2:5]), Side(row[5]), _int(row[6]), _num(row[7]), extended)


def _user(d: object) -> User:
    if not isinstance(d, dict) or not isinstance(d["joints"], dict) or len(d["joints"]) > MAX_JOINTS:
        raise ValueError(f"a user must be an object with at most {MAX_JOINTS} joints")
    joints = {}
    for name, row in d["joints"].items():
        if len(name) > MAX_NAME or not isinstance(row, list) or len(row) != 4:
            raise ValueError(f"joint {name[:MAX_NAME]!r}: expected a short name and [x, y, z, confidence]")
        joints[name] = Joint(_vec(row[:3]), _num(row[3]))
    com = d["com"]
    return User(_int(d["id"]), HandState(d["state"]), joints, None if com is None else _vec(com))


def _hands(h: Header, d: dict) -> HandsMsg:
    rows = d["hands"]
    if not isinstance(rows, list) or not isinstance(d["backend"], str):
        raise ValueError("hands must be a list and backend a string")
    return HandsMsg(h, _int(d["frame"]), _num(d["t"]), d["backend"][:64], tuple(_hand(r) for r in rows),
                    bool(d["depth"]), tuple(_user(u) for u in _list(d.get("users", []), MAX_USERS)))


def _gesture(h: Header, d: dict) -> GestureMsg:
    g = Gesture(GestureType(d["type"]), GestureState(d["state"]), _vec(d["position"]), _int(d["hand"]),
                Side(d["side"]), _num(d["confidence"]), _num(d["t"]), label=_label(d.get("name", "")),
                hands=tuple(_int(i) for i in _list(d.get("hands", []), 2)), user_id=_int(d.get("user", 1)))
    return GestureMsg(h, _int(d["frame"]), g)


def _label(v: object) -> str:
    """A learned gesture's name (the key is absent for the built-in dictionary)."""
    if not isinstance(v, str) or len(v) > 64:
        raise ValueError("a gesture name must be a string of at most 64 characters")
    return v


def _list(v: object, longest: int) -> list:
    if not isinstance(v, list) or len(v) > longest:
        raise ValueError(f"expected a list of at most {longest} items")
    return v


def _status(h: Header, d: dict) -> StatusMsg:
    last = d["last"]
    if not isinstance(last, dict):
        raise ValueError("last must be an object")
    return StatusMsg(h, {k: _int(last[k]) for k in STREAMS.values()}, str(d["backend"])[:64],
                     _int(d["depth_skipped"]))


_JSON_DECODERS = {HANDS: _hands, GESTURE: _gesture, HEARTBEAT: _status, BYE: _status}
