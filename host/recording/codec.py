"""How issv frames become MCAP messages and back (the recording format, issv-recording/1).

Channels (one per kind of data, so standard MCAP tools can filter them):

- `/depth`, message encoding `issv-depth-zstd`, no schema: one message per depth image. The bytes
  are a UTF-8 JSON header, a newline, then the image: row-major little-endian uint16 millimetres
  (0 = no reading) compressed with zstd (lossless). Header keys: `frame_id`, `t` (source seconds),
  `capture_time` (wall clock, s), `width`, `height`, `intrinsics` [fx, fy, cx, cy] (pixels),
  `mirrored`, `truth` (null, or the source's ground truth: `hands` {side: [x, y, z]}, `gestures`
  [{name, side, start, end}], `body` {joint: [x, y, z]}, and for a scene of several performers
  `users` [{id, hands, gestures, body}], each performer in view with the same keys).
- `/user_labels`, message encoding `issv-labels-zstd`, no schema: the user label image of a depth
  image, written right after it when the backend knows which user is where (Frame.user_labels).
  A UTF-8 JSON header (`frame_id`: the depth image's, `width`, `height`), a newline, then the
  row-major uint8 labels (0 nobody, else the user's id) compressed with zstd. Optional: recordings
  of backends without labels, and those made before this channel existed, have none (and read as
  before: an older issv skips the channel).
- `/gestures`, `json` (schema `issv.Gesture`): one message per gesture event, keys as in the event
  lines of docs/architecture.md (`t`, `name`, `native`, `state`, `hand`, `side`, `position`, `confidence`) at
  full precision, plus `seq`, the frame that carried it.
- `/hands`, `json` (schema `issv.Hands`): one message per sensor frame, written last for that
  frame: `seq`, `t`, `capture_time`, `backend`, `depth_id` (the `frame_id` of its depth image, or
  null), `hands` [{id, state, side, position, user_id, confidence, extended}], and, when the
  backend tracks users, `users` [{id, state, center_of_mass, joints {name: {position, confidence}}}].
- `/metrics`, `json` (schema `issv.Metrics`): the `--metrics-json` document about once a second
  and once at the end (`final`: true).

Message log times are source time in nanoseconds (what `seek` uses); publish times are the host's
wall clock at capture. A frame is: its depth message (if any), its gestures, then its hands.
Gestures after the last frame's hands were completed by the end of the source (Backend.finish()).
"""
from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np
import zstandard

from host import compression
from host.model import (DepthFrame, Frame, Gesture, GestureState, GestureType, Hand, HandState,
                        Intrinsics, Side, Truth, TruthGesture, User, UserTruth)

FORMAT = "issv-recording/1"
DEPTH, HANDS, GESTURES, METRICS = "/depth", "/hands", "/gestures", "/metrics"
LABELS = "/user_labels"
DEPTH_ENCODING = "issv-depth-zstd"
LABELS_ENCODING = "issv-labels-zstd"

_VEC = {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3,
        "description": "millimetres, camera coordinates: x right, y up, z away"}
SCHEMAS: dict[str, dict] = {
    GESTURES: {
        "title": "issv.Gesture", "type": "object",
        "properties": {
            "seq": {"type": "integer"}, "t": {"type": "number", "description": "source seconds"},
            "name": {"type": "string", "description": "canonical name, e.g. wave"},
            "native": {"enum": [g.value for g in GestureType]},
            "state": {"enum": [s.value for s in GestureState]}, "hand": {"type": "integer"},
            "side": {"enum": [s.value for s in Side]}, "position": _VEC,
            "confidence": {"type": "number", "minimum": 0, "maximum": 1},
        },
        "required": ["seq", "t", "native", "state", "hand", "side", "position", "confidence"],
    },
    HANDS: {
        "title": "issv.Hands", "type": "object",
        "properties": {
            "seq": {"type": "integer"}, "t": {"type": "number"}, "capture_time": {"type": "number"},
            "backend": {"type": "string"}, "depth_id": {"type": ["integer", "null"]},
            "hands": {"type": "array", "items": {"type": "object", "properties": {
                "id": {"type": "integer"}, "state": {"enum": [s.value for s in HandState]},
                "side": {"enum": [s.value for s in Side]}, "position": _VEC,
                "user_id": {"type": "integer"}, "confidence": {"type": "number"},
                "extended": {"type": ["boolean", "null"]}}}},
            "users": {"type": "array", "items": {"type": "object", "properties": {
                "id": {"type": "integer"}, "state": {"enum": [s.value for s in HandState]},
                "center_of_mass": {"oneOf": [_VEC, {"type": "null"}]},
                "joints": {"type": "object", "additionalProperties": {"type": "object", "properties": {
                    "position": _VEC, "confidence": {"type": "number"}}}}}}},
        },
        "required": ["seq", "t", "capture_time", "backend", "depth_id", "hands"],
    },
    METRICS: {"title": "issv.Metrics", "type": "object",
              "description": "the --metrics-json document of `issv run`, plus `final`"},
}


class FormatError(ValueError):
    """A message that does not follow issv-recording/1 (the reader adds the file and offset)."""


def seconds_to_ns(t: float) -> int:
    return max(0, int(round(t * 1e9)))


def _vec(p) -> tuple[float, float, float]:
    return (float(p[0]), float(p[1]), float(p[2]))


def _gestures_to_json(gestures) -> list[dict]:
    return [{"name": g.name, "side": g.side.value, "start": g.start, "end": g.end} for g in gestures]


def _gestures_from_json(docs: list[dict]) -> tuple[TruthGesture, ...]:
    return tuple(TruthGesture(g["name"], Side(g["side"]), float(g["start"]), float(g["end"])) for g in docs)


def truth_to_json(truth: Truth | None) -> dict | None:
    if truth is None:
        return None
    doc = {"hands": {s.value: list(p) for s, p in truth.hands.items()},
           "gestures": _gestures_to_json(truth.gestures),
           "body": {k: list(p) for k, p in truth.body.items()}}
    if truth.users:
        doc["users"] = [{"id": u.id, "hands": {s.value: list(p) for s, p in u.hands.items()},
                         "gestures": _gestures_to_json(u.gestures), "body": {k: list(p) for k, p in u.body.items()}}
                        for u in truth.users]
    return doc


def truth_from_json(doc: dict | None) -> Truth | None:
    """A recording's truth; `users` is absent from recordings of one performer and older ones."""
    if doc is None:
        return None
    return Truth(hands={Side(s): _vec(p) for s, p in doc.get("hands", {}).items()},
                 gestures=_gestures_from_json(doc.get("gestures", [])),
                 body={k: _vec(p) for k, p in doc.get("body", {}).items()},
                 users=tuple(UserTruth(int(u["id"]), {Side(s): _vec(p) for s, p in u.get("hands", {}).items()},
                                       {k: _vec(p) for k, p in u.get("body", {}).items()},
                                       _gestures_from_json(u.get("gestures", [])))
                             for u in doc.get("users", [])))


def encode_depth(depth: DepthFrame) -> bytes:
    header = {"frame_id": depth.frame_id, "t": depth.timestamp, "capture_time": depth.capture_time,
              "width": depth.width, "height": depth.height, "intrinsics": depth.intrinsics.as_list(),
              "mirrored": depth.mirrored, "truth": truth_to_json(depth.truth)}
    pixels = depth.data.astype("<u2", copy=False)  # C-contiguous (DepthFrame sees to it): zstd reads it in place
    # level 1, the fastest: this runs on the sensor thread; level 3 saves ~2 %
    return json.dumps(header).encode() + b"\n" + compression.compressor().compress(pixels)


@dataclass(frozen=True)
class DepthHeader:
    """A depth message's header and its still-compressed pixels (decoded only when needed)."""

    doc: dict
    payload: bytes

    @property
    def t(self) -> float:
        return float(self.doc["t"])

    @property
    def frame_id(self) -> int:
        return int(self.doc["frame_id"])

    def decode(self) -> DepthFrame:
        d = self.doc
        w, h = int(d["width"]), int(d["height"])
        try:
            raw = compression.decompressor().decompress(self.payload, max_output_size=w * h * 2)
        except zstandard.ZstdError as error:
            raise FormatError(f"depth frame {d['frame_id']}: its pixels do not decompress ({error})") from None
        if len(raw) != w * h * 2:
            raise FormatError(f"depth frame {d['frame_id']}: {len(raw)} bytes of pixels for {w}x{h}")
        data = np.frombuffer(raw, dtype="<u2").astype(np.uint16, copy=False).reshape(h, w)  # DepthFrame copies it
        return DepthFrame(data, Intrinsics(*map(float, d["intrinsics"])), frame_id=int(d["frame_id"]),
                          timestamp=float(d["t"]), capture_time=float(d["capture_time"]),
                          mirrored=bool(d["mirrored"]), truth=truth_from_json(d.get("truth")))


def encode_labels(depth: DepthFrame, labels: np.ndarray) -> bytes:
    """The label image of `depth` (same size): a few KB where the raw image is ~300 KB at 640x480."""
    if labels.shape != depth.data.shape:
        raise ValueError(f"user labels of shape {labels.shape} for a depth image of shape {depth.data.shape}")
    header = {"frame_id": depth.frame_id, "width": depth.width, "height": depth.height}
    return (json.dumps(header).encode() + b"\n"
            + compression.compressor().compress(np.ascontiguousarray(labels, np.uint8)))


def decode_labels(data: bytes) -> tuple[int, np.ndarray]:
    """(frame_id of the depth image they belong to, uint8 labels)."""
    head, sep, payload = data.partition(b"\n")
    if not sep:
        raise FormatError("user labels message has no JSON header line")
    doc = decode_json(head)
    try:
        frame_id, w, h = int(doc["frame_id"]), int(doc["width"]), int(doc["height"])
    except (KeyError, TypeError, ValueError) as error:
        raise FormatError(f"user labels header lacks a usable `frame_id`, `width` or `height` ({error})") from None
    try:
        raw = compression.decompressor().decompress(payload, max_output_size=w * h)
    except zstandard.ZstdError as error:
        raise FormatError(f"user labels of depth frame {frame_id}: they do not decompress ({error})") from None
    if len(raw) != w * h:
        raise FormatError(f"user labels of depth frame {frame_id}: {len(raw)} bytes for {w}x{h}")
    return frame_id, np.frombuffer(raw, np.uint8).reshape(h, w)


def decode_depth(data: bytes) -> DepthHeader:
    head, sep, payload = data.partition(b"\n")
    if not sep:
        raise FormatError("depth message has no JSON header line")
    doc = decode_json(head)
    for key in ("frame_id", "t", "capture_time", "width", "height", "intrinsics", "mirrored"):
        if key not in doc:
            raise FormatError(f"depth message header has no `{key}`")
    return DepthHeader(doc, payload)


def decode_json(data: bytes) -> dict:
    try:
        doc = json.loads(data)
    except (UnicodeDecodeError, json.JSONDecodeError) as error:
        raise FormatError(f"message is not valid JSON ({error})") from None
    if not isinstance(doc, dict):
        raise FormatError("message is not a JSON object")
    return doc


def hand_to_json(h: Hand) -> dict:
    return {"id": h.id, "state": h.state.value, "side": h.side.value, "position": list(h.position),
            "user_id": h.user_id, "confidence": h.confidence, "extended": h.extended}


def hand_from_json(d: dict) -> Hand:
    extended = d.get("extended")
    return Hand(int(d["id"]), HandState(d["state"]), _vec(d["position"]), Side(d["side"]),
                int(d.get("user_id", 1)), float(d.get("confidence", 1.0)),
                None if extended is None else bool(extended))


def gesture_to_json(g: Gesture, seq: int) -> dict:
    return {"seq": seq, "t": g.timestamp, "type": "gesture", "name": g.name, "native": g.type.value,
            "state": g.state.value, "hand": g.hand_id, "side": g.side.value, "position": list(g.position),
            "confidence": g.confidence, "user_id": g.user_id, **({"hands": list(g.hands)} if g.hands else {})}


def gesture_from_json(d: dict) -> Gesture:
    kind = GestureType(d["native"])
    return Gesture(kind, GestureState(d["state"]), _vec(d["position"]), int(d["hand"]),
                   Side(d["side"]), float(d["confidence"]), float(d["t"]), int(d.get("user_id", 1)),
                   label=str(d["name"]) if kind is GestureType.LEARNED else "",
                   hands=tuple(int(h) for h in d.get("hands", ())))


def hands_to_json(frame: Frame) -> dict:
    return {"seq": frame.seq, "t": frame.timestamp, "capture_time": frame.capture_time,
            "backend": frame.backend, "depth_id": frame.depth.frame_id if frame.depth is not None else None,
            "hands": [hand_to_json(h) for h in frame.hands],
            **({"users": [u.to_json() for u in frame.users]} if frame.users else {})}


def users_from_json(doc: dict) -> tuple[User, ...]:
    return tuple(User.from_json(u) for u in doc.get("users", ()))


def checked(decode, doc: dict, what: str):
    """Run a decoder; a missing key or a bad value becomes a FormatError naming the message."""
    try:
        return decode(doc)
    except (KeyError, ValueError, TypeError, IndexError) as error:
        raise FormatError(f"{what} message is malformed ({type(error).__name__}: {error})") from None
