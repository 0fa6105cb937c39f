"""10,000 random and truncated messages over a real socket never crash the subscriber; each kind
of problem is counted, and reported once."""
from __future__ import annotations

import json
import random
import time

import numpy as np
import zmq

from backends.network import wire
from backends.network.backend import NetworkBackend, NetworkOptions
from host import DepthFrame, Gesture, GestureState, GestureType, Hand, HandState, Intrinsics, Side, frames_of
from tests.backends.network.conftest import free_ports

N = 10_000


def valid_messages() -> list[bytes]:
    depth = DepthFrame(np.random.default_rng(0).integers(0, 4000, (60, 80)).astype(np.uint16),
                       Intrinsics(70, 70, 40, 30))
    g = Gesture(GestureType.WAVE, GestureState.COMPLETE, (1.0, 2.0, 3.0), 1, Side.LEFT, 0.9, 1.0)
    hands = (Hand(1, HandState.TRACKING, (1.0, 2.0, 3.0), Side.LEFT),)
    return [wire.encode_depth(1, 1, 0.0, 1, depth), wire.encode_gesture(1, 1, 0.0, 1, g),
            wire.encode_hands(1, 1, 0.0, 1, 0.0, "x", hands, False)]


def hostile(rng: random.Random) -> list[list[bytes]]:
    """Random bytes, truncated valid messages, valid headers with junk bodies, JSON of the wrong
    shape, unknown kinds and versions, multipart messages: N in all, none of them decodable."""
    valid = valid_messages()
    out: list[list[bytes]] = []
    for i in range(N):
        pick = i % 6
        if pick == 0:
            out.append([rng.randbytes(rng.randrange(0, 300))])
        elif pick == 1:
            m = rng.choice(valid)
            out.append([m[:rng.randrange(0, len(m))]])
        elif pick == 2:
            kind = rng.choice([wire.DEPTH, wire.HANDS, wire.GESTURE, wire.HEARTBEAT, wire.BYE])
            out.append([wire.header(kind, 1, i, 0.0) + rng.randbytes(rng.randrange(0, 200))])
        elif pick == 3:
            doc = rng.choice([[], 1, "x", {"frame": "1"}, {"hands": [[1] * 8], "frame": 1, "t": 0, "backend": "x",
                                                          "depth": 0}, {"last": {"depth": -1}}])
            kind = rng.choice([wire.HANDS, wire.GESTURE, wire.HEARTBEAT])
            out.append([wire.header(kind, 1, i, 0.0) + json.dumps(doc).encode()])
        elif pick == 4:
            out.append([wire.header(rng.choice([0, 6, 200]), 1, i, 0.0) if (i // 6) % 2 else
                        wire.MAGIC + bytes([9]) + bytes(40)])
        else:
            out.append([rng.choice(valid), rng.randbytes(10)])
    return out


def test_ten_thousand_hostile_messages_are_counted_and_the_show_goes_on(capsys):
    port = free_ports()
    ctx = zmq.Context()
    events, depth = ctx.socket(zmq.XPUB), ctx.socket(zmq.PUB)
    events.setsockopt(zmq.SNDHWM, 0)
    events.bind(f"tcp://127.0.0.1:{port}")
    depth.bind(f"tcp://127.0.0.1:{port + 1}")
    backend = NetworkBackend(None, NetworkOptions(connect=f"tcp://127.0.0.1:{port}", depth_wait_ms=0))
    try:
        with backend:
            assert events.poll(5000) and events.recv()[:1] == b"\x01"  # the subscriber has joined
            for parts in hostile(random.Random(9)):
                events.send_multipart(parts)
            for _ in range(200):
                depth.send(random.randbytes(100))
            time.sleep(0.2)
            hands = (Hand(3, HandState.TRACKING, (10.0, 20.0, 2000.0), Side.RIGHT),)
            events.send(wire.encode_hands(7, 1, time.time(), 1, 0.5, "remote", hands, False))
            frame = next(frames_of(backend), None)  # all the junk first, then the one good message
            stats = backend.stats()
    finally:
        ctx.destroy(linger=0)
    assert frame is not None and frame.hands == hands and frame.backend == "remote"
    counted = sum(stats["malformed"].values())
    assert N <= counted <= N + 200
    assert {"bad-magic", "truncated", "bad-json", "bad-field", "unknown-kind", "bad-version", "multipart"} \
        <= set(stats["malformed"])
    err = capsys.readouterr().err
    for kind in stats["malformed"]:
        assert err.count(f"further `{kind}` messages are counted") == 1
    assert stats["streams"]["hands"]["received"] == 1


def test_a_frame_still_waiting_when_the_publisher_ends_keeps_its_backend_name():
    """The last hands message waits for a depth image that never comes; the publisher's goodbye
    flushes it, named after the backend that made it like every other frame."""
    port = free_ports()
    ctx = zmq.Context()
    events, depth = ctx.socket(zmq.XPUB), ctx.socket(zmq.PUB)
    events.bind(f"tcp://127.0.0.1:{port}")
    depth.bind(f"tcp://127.0.0.1:{port + 1}")
    options = NetworkOptions(connect=f"tcp://127.0.0.1:{port}", depth_wait_ms=1000, end_with_publisher=True)
    hands = (Hand(3, HandState.TRACKING, (10.0, 20.0, 2000.0), Side.RIGHT),)
    try:
        with NetworkBackend(None, options) as backend:
            assert events.poll(5000) and events.recv()[:1] == b"\x01"  # the subscriber has joined
            events.send(wire.encode_hands(7, 1, time.time(), 1, 0.5, "remote", hands, True))
            events.send(wire.encode_status(wire.BYE, 7, 1, {"hands": 1, "gestures": 0, "depth": 0}, "remote", 0,
                                           time.time()))
            frames = list(frames_of(backend))
    finally:
        ctx.destroy(linger=0)
    assert [(f.hands, f.backend) for f in frames] == [(hands, "remote")]
