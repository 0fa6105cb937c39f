"""The wire format: lossless depth codecs, cropping and downscaling, events that survive the trip."""
from __future__ import annotations

import numpy as np
import pytest

from backends.network import wire
from backends.network.publisher import DepthOptions, endpoints
from host import DepthFrame, Gesture, GestureState, GestureType, Hand, HandState, Intrinsics, Joint, Side, User
from sources.clip import Clip


def noisy_depth(seed: int = 1) -> np.ndarray:
    rng = np.random.default_rng(seed)
    data = (rng.normal(2500, 400, (48, 64)).clip(0, 65535)).astype(np.uint16)
    data[rng.random(data.shape) < 0.1] = 0
    data[0, 0], data[-1, -1] = 65535, 0  # extremes survive the uint16 wrap-around of a delta
    return data


@pytest.mark.parametrize("codec", sorted(wire.CODECS))
def test_every_codec_gives_back_the_exact_image(codec, performer_clip):
    images = [noisy_depth(), Clip(performer_clip).depth[10]]
    for img in images:
        blob = wire.CODECS[codec].encode(img)
        assert np.array_equal(wire.CODECS[codec].decode(blob, img.shape), img)


def test_depth_message_round_trip_keeps_image_intrinsics_and_times():
    depth = DepthFrame(noisy_depth(), Intrinsics(50.0, 51.0, 32.0, 24.0), frame_id=7, timestamp=1.25,
                       capture_time=1000.5, mirrored=False)
    msg = wire.decode(wire.encode_depth(99, 3, depth.capture_time, 12, depth))
    assert isinstance(msg, wire.DepthMsg)
    assert (msg.header.session, msg.header.seq, msg.header.capture_time, msg.frame_seq) == (99, 3, 1000.5, 12)
    assert np.array_equal(msg.depth.data, depth.data)
    assert msg.depth.intrinsics == depth.intrinsics
    assert (msg.depth.frame_id, msg.depth.timestamp, msg.depth.mirrored) == (7, 1.25, False)


def test_crop_and_downscale_keep_millimetres_and_pixels_consistent():
    intr = Intrinsics(60.0, 60.0, 32.0, 24.0)
    depth = DepthFrame(noisy_depth(), intr)
    shaped = DepthOptions(crop=(8, 4, 40, 30), downscale=2).shape(depth)
    assert shaped.data.shape == (15, 20)
    assert np.array_equal(shaped.data, depth.data[4:34:2, 8:48:2])
    # the same world point lands on the same depth value in both images
    u, v = 20, 10  # in the shaped image
    world = shaped.depth_to_world(u, v, 2000.0)
    U, V, _ = depth.world_to_depth(world)
    assert (round(U), round(V)) == (8 + 2 * u, 4 + 2 * v)


def test_hands_and_gestures_round_trip():
    hands = (Hand(1, HandState.NEW, (1.5, -2.0, 2000.0), Side.LEFT, 2, 0.5),
             Hand(2, HandState.TRACKING, (3.0, 4.0, 2100.0), Side.RIGHT))
    msg = wire.decode(wire.encode_hands(5, 1, 10.0, 42, 1.5, "truth", hands, True))
    assert isinstance(msg, wire.HandsMsg)
    assert (msg.hands, msg.frame_seq, msg.timestamp, msg.backend, msg.depth) == (hands, 42, 1.5, "truth", True)
    g = Gesture(GestureType.SWIPE_LEFT, GestureState.COMPLETE, (1.0, 2.0, 3.0), 2, Side.RIGHT, 0.75, 3.5)
    back = wire.decode(wire.encode_gesture(5, 9, 10.0, 42, g))
    assert isinstance(back, wire.GestureMsg) and back.gesture == g and back.header.seq == 9


USERS = (User(3, HandState.TRACKING, {"torso": Joint((10.0, 200.0, 2200.0)), "left_hand": Joint((-300.0, 0.0, 2180.0), 0.4)},
              (12.5, 150.0, 2200.0)),
         User(4, HandState.NEW))


def test_users_resting_hands_and_gesture_users_round_trip():
    hands = (Hand(31, HandState.TRACKING, (-300.0, 0.0, 2180.0), Side.LEFT, 3, 0.9, extended=False),
             Hand(32, HandState.TRACKING, (300.0, 400.0, 1800.0), Side.RIGHT, 3, 1.0, extended=True))
    msg = wire.decode(wire.encode_hands(5, 1, 10.0, 42, 1.5, "openiss", hands, False, USERS))
    assert msg.hands == hands and msg.users == USERS
    g = Gesture(GestureType.WAVE, GestureState.COMPLETE, (1.0, 2.0, 3.0), 32, Side.RIGHT, user_id=3)
    assert wire.decode(wire.encode_gesture(5, 9, 10.0, 42, g)).gesture.user_id == 3


def test_version_1_messages_are_still_read():
    """What an issv before users sent: version 1, 8-value hand rows, no users, gestures without a user."""
    head = wire.HEADER.pack(wire.MAGIC, 1, wire.HANDS, 0, 5, 1, 10.0)
    msg = wire.decode(head + b'{"frame":42,"t":1.5,"backend":"truth","depth":true,'
                             b'"hands":[[1,"tracking",1.5,-2.0,2000.0,"left",2,0.5]]}')
    assert msg.hands == (Hand(1, HandState.TRACKING, (1.5, -2.0, 2000.0), Side.LEFT, 2, 0.5),) and msg.users == ()
    head = wire.HEADER.pack(wire.MAGIC, 1, wire.GESTURE, 0, 5, 2, 10.0)
    g = wire.decode(head + b'{"frame":42,"type":"WAVE","state":"complete","position":[0,0,0],"hand":1,'
                           b'"side":"left","confidence":1,"t":0}').gesture
    assert g.user_id == 1 and g.name == "wave"
    with pytest.raises(wire.WireError, match="bad-version: version 4, this issv reads 1, 2 and 3"):
        wire.decode(wire.HEADER.pack(wire.MAGIC, 4, wire.HANDS, 0, 5, 1, 10.0) + b"{}")


def test_learned_gestures_keep_their_name_and_hands_on_the_wire():
    g = Gesture(GestureType.LEARNED, GestureState.IN_PROGRESS, (1.0, 2.0, 3.0), 0, Side.UNKNOWN, 0.8, 3.5,
                label="wind_it_up", hands=(1, 2))
    back = wire.decode(wire.encode_gesture(5, 9, 10.0, 42, g)).gesture
    assert back == g and back.name == "wind_it_up"


@pytest.mark.parametrize("bad, kind", [
    (b"", "truncated"),
    (b"XXXX" + bytes(40), "bad-magic"),
    (wire.header(77, 1, 1, 0.0), "unknown-kind"),
    (wire.header(wire.HANDS, 1, 1, 0.0) + b"{not json", "bad-json"),
    (wire.header(wire.HANDS, 1, 1, 0.0) + b'{"frame": 1}', "bad-field"),
    (wire.header(wire.HANDS, 1, 1, 0.0) + b'{"frame":1,"t":0,"backend":"x","depth":false,"hands":[],'
                                           b'"users":[{"id":1,"state":"tracking","com":null,"joints":{"head":[0,0]}}]}',
     "bad-field"),
    (wire.header(wire.HANDS, 1, 1, 0.0) + b'{"frame":1,"t":0,"backend":"x","depth":false,'
                                           b'"hands":[[1,"tracking",0,0,1,"left",1,1,"yes"]]}', "bad-field"),
    (wire.header(wire.GESTURE, 1, 1, 0.0) + b'{"frame":1,"type":"DANCE","state":"complete","position":[0,0,0],'
                                             b'"hand":1,"side":"left","confidence":1,"t":0}', "bad-field"),
    (wire.header(wire.GESTURE, 1, 1, 0.0) + b'{"frame":1,"type":"learned","state":"complete","position":[0,0,0],'
                                             b'"hand":1,"side":"left","confidence":1,"t":0,"name":7}', "bad-field"),
    (wire.header(wire.DEPTH, 1, 1, 0.0) + wire.DEPTH_BODY.pack(1, 1, 0.0, 60000, 60000, 1, 0, 1, 1, 1, 1), "bad-depth"),
])
def test_malformed_messages_name_what_is_wrong(bad, kind):
    with pytest.raises(wire.WireError) as error:
        wire.decode(bad)
    assert error.value.kind == kind


def test_a_compressed_bomb_is_refused_not_inflated():
    bomb = wire.CODECS["zstd"].encode(np.zeros((2000, 2000), np.uint16))  # claims 10x10 below
    msg = wire.header(wire.DEPTH, 1, 1, 0.0) + wire.DEPTH_BODY.pack(1, 1, 0.0, 10, 10, 1, 0, 1, 1, 1, 1) + bomb
    with pytest.raises(wire.WireError) as error:
        wire.decode(msg)
    assert error.value.kind == "bad-depth"


def _banded_message(payload: bytes, width: int = 64, height: int = 48) -> bytes:
    codec = wire.CODECS["banded-zstd"].id
    return (wire.header(wire.DEPTH, 1, 1, 0.0) + wire.DEPTH_BODY.pack(1, 1, 0.0, width, height, codec, 0, 1, 1, 1, 1)
            + payload)


def test_banded_depth_steps_aside_between_bands_and_comes_back_exact():
    image = np.tile(noisy_depth(), (10, 10))  # 480 x 640: several bands
    pauses = []
    blob = wire.CODECS["banded-zstd"].encode(image, lambda: pauses.append(1))
    assert len(pauses) == int.from_bytes(blob[:2], "little") > 1
    msg = wire.decode(_banded_message(blob, 640, 480))
    assert np.array_equal(msg.depth.data, image)


@pytest.mark.parametrize("damage", ["no bands", "more bands than rows", "sizes too long", "band swapped"])
def test_a_lying_band_table_is_refused(damage):
    image = np.vstack([noisy_depth(seed) for seed in range(40)])  # 1920 x 64: several different bands
    blob = wire.CODECS["banded-zstd"].encode(image)
    n = int.from_bytes(blob[:2], "little")
    sizes = list(np.frombuffer(blob[2:2 + 4 * n], np.uint32))
    bands = blob[2 + 4 * n:]
    if damage == "no bands":
        payload = (0).to_bytes(2, "little")
    elif damage == "more bands than rows":
        payload = (2000).to_bytes(2, "little") + blob[2:]
    elif damage == "sizes too long":
        payload = blob[:2] + np.array([*sizes[:-1], sizes[-1] + 9], np.uint32).tobytes() + bands
    else:  # the first two bands' sizes exchanged: each decompresses to the wrong number of rows
        sizes[0], sizes[1] = sizes[1], sizes[0]
        payload = blob[:2] + np.array(sizes, np.uint32).tobytes() + bands
    with pytest.raises(wire.WireError) as error:
        wire.decode(_banded_message(payload, 64, 1920))
    assert error.value.kind == "bad-depth"


def test_addresses_are_checked_and_depth_uses_the_next_port():
    assert endpoints("tcp://10.0.0.2:6000") == ("tcp://10.0.0.2:6000", "tcp://10.0.0.2:6001")
    with pytest.raises(ValueError, match="tcp://HOST:PORT"):
        endpoints("localhost:5555")
