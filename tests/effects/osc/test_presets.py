"""OSCeleton, Synapse and templates: exact addresses, type tags and values on a real socket."""
from pathlib import Path

import pytest

from host import Side, TruthGesture
from host.errors import ProfileError
from host.profile import parse
from tests.effects.osc.helpers import FPS, K, Script, hand_at, make_osc, run_show


def frame_of(z_mm: float) -> int:
    """The scripted performer walks away 10 mm a frame from 2 m: its depth says which frame it is."""
    return round((z_mm - 2000.0) / 10)


def test_osceleton_joints_users_and_ranges(receiver):
    script = Script(n=12, hands=lambda i: (Side.LEFT, Side.RIGHT) if i < 8 else (), gestures=())
    run_show([make_osc(destinations=[receiver.address], scheme="osceleton")], realtime=True, script=script)
    assert receiver.wait_for(lambda r: r.messages("/lost_user"))
    messages = receiver.messages()
    assert messages[:2] == [("/new_user", "i", [1]), ("/new_skel", "i", [1])]
    assert messages[-1] == ("/lost_user", "i", [1])
    joints = [m for m in messages if m[0] == "/joint"]
    assert len(joints) >= 12 and {m[1] for m in joints} == {"sifff"}  # 2 per frame, 8 frames (or a few less)
    for _, _, (name, user, x, y, z) in joints:
        side = {"l_hand": Side.LEFT, "r_hand": Side.RIGHT}[name]
        X, Y, Z = hand_at(side, frame_of(z * 1280))
        assert user == 1
        assert (x, y, z) == pytest.approx(((X + 1280) / 2560, (960 - Y) / 1920, Z * 7.8125 / 10000), rel=1e-6)
        assert 0 <= x <= 1 and 0 <= y <= 1 and 0 < z < 7


def test_synapse_positions_tracking_and_gesture_words(receiver):
    script = Script(n=24, hands=lambda i: (Side.LEFT, Side.RIGHT) if i < 22 else (),
                    gestures=(TruthGesture("swipe_left", Side.LEFT, 5 / FPS, 8 / FPS),
                              TruthGesture("click", Side.RIGHT, 10 / FPS, 12 / FPS),
                              TruthGesture("hand_raise", Side.RIGHT, 14 / FPS, 16 / FPS)))
    run_show([make_osc(destinations=[receiver.address], scheme="synapse", in_progress=True, keepalive="off")], realtime=True,
             script=script)
    assert receiver.wait_for(lambda r: r.messages("/tracking_skeleton")[-1:] == [("/tracking_skeleton", "i", [0])])
    messages = receiver.messages()
    assert messages[0] == ("/tracking_skeleton", "i", [1])
    assert {m[0] for m in messages} == {"/tracking_skeleton", "/lefthand_pos_world", "/righthand_pos_world",
                                        "/lefthand_pos_screen", "/righthand_pos_screen", "/lefthand", "/righthand",
                                        "/closesthand_pos_world", "/closesthand_pos_screen"}
    assert all(m[1] == "fff" for m in messages if m[0].endswith(("_world", "_screen")))
    # only completed gestures, as words, on the joint that made them (in_progress is not Synapse's)
    assert [m for m in messages if m[0] in ("/lefthand", "/righthand")] == [
        ("/lefthand", "s", ["left"]), ("/righthand", "s", ["forward"]), ("/righthand", "s", ["hand_raise"])]
    world = [m[2] for m in messages if m[0] == "/righthand_pos_world"]
    screen = [m[2] for m in messages if m[0] == "/righthand_pos_screen"]
    assert len(world) == len(screen) >= 15
    for (x, y, z), (u, v, depth) in zip(world, screen):
        i = frame_of(z)
        assert (x, y, z) == pytest.approx(hand_at(Side.RIGHT, i), rel=1e-6)
        # the scripted camera is 640x480 already, so Synapse's screen is its depth image
        assert (u, v, depth) == pytest.approx(K.world_to_depth(*hand_at(Side.RIGHT, i)), rel=1e-5)


def test_a_hand_of_unknown_side_takes_the_free_side():
    from effects.osc.presets import sided
    from host import Hand, HandState

    hands = [Hand(1, HandState.TRACKING, (0, 0, 1), Side.UNKNOWN), Hand(2, HandState.TRACKING, (0, 0, 1), Side.RIGHT),
             Hand(3, HandState.TRACKING, (0, 0, 1), Side.UNKNOWN), Hand(4, HandState.TRACKING, (0, 0, 1), Side.UNKNOWN)]
    assert [(h.id, s) for h, s in sided(hands)] == [(1, Side.LEFT), (2, Side.RIGHT)]


def test_templates_fill_fields_with_their_types(receiver):
    effect = make_osc(destinations=[receiver.address], scheme="custom", pd_safe=False, messages=[
        {"on": "frame", "address": "/f", "args": ["{seq}", "{capture_time}", "{hands}"]},
        {"on": "hand", "address": "{prefix}/{side}/xyz", "args": ["{x}", "{y}", "{z}", "{tracking}", "id{id}", 7]},
        {"on": "gesture", "address": "/g/{name}", "args": ["{complete}", "{hand}", "{native}", "{x_mm}", 2**40]},
    ])
    run_show([effect], script=Script(n=20))
    assert receiver.wait_for(lambda r: r.has_frame(20, "/f"))
    frame = receiver.messages("/f")[-1]
    assert frame[1] == "idi" and frame[2][0] == 20 and frame[2][2] == 2 and frame[2][1] > 1.7e9
    right = receiver.messages("/right/xyz")[-1]
    assert right[1] == "fffTsi" and right[2][3:] == [True, "id2", 7]
    assert right[2][:3] == pytest.approx(hand_at(Side.RIGHT, 19), rel=1e-6)
    assert receiver.messages("/g/wave") == [("/g/wave", "Tisfh", [True, 2, "WAVE", pytest.approx(hand_at(Side.RIGHT, 9)[0]), 2**40])]
    assert receiver.messages("/issv/frame") == []


def test_templates_add_to_a_scheme_and_pd_safe_converts_them(receiver):
    effect = make_osc(destinations=[receiver.address], messages=[
        {"on": "gesture", "address": "/g", "args": ["{complete}", "{name}", 2**40]}])
    run_show([effect], script=Script(n=20))
    assert receiver.wait_for(lambda r: len(r.messages("/g")) == 2)
    assert receiver.messages("/g")[0] == ("/g", "isf", [1, "wave", float(2**40)])
    assert len(receiver.messages("/issv/gesture")) == 2


@pytest.mark.parametrize("effect, message", [
    ('scheme = "custom"', 'scheme "custom" sends only the templates'),
    ('destinations = ["localhost"]', "expected HOST:PORT"),
    ('destinations = ["localhost:70000"]', "port must be 1..65535"),
    ('prefix = "issv"', "expected an OSC address part"),
    ('gestures = ["jump"]', "effects[0].gestures[0]"),
    ('[[effects.messages]]\non = "hand"\naddress = "/h"\nargs = ["{nme}"]', "unknown field {nme} for on = 'hand'"),
    ('[[effects.messages]]\non = "frame"\naddress = "h/{seq}"', "address must start with /"),
    ('scheme = "synapse"\nkeepalive = "12346"', 'keepalive: expected HOST:PORT such as 127.0.0.1:9000, or "off"'),
    ('scheme = "osceleton"\nkeepalive = "off"', 'keepalive is Synapse\'s keep-alive port: it needs scheme = "synapse"'),
])
def test_bad_options_name_the_key(effect, message):
    text = f'backend = "truth"\n[[effects]]\nname = "osc"\n{effect}\n'
    with pytest.raises(ProfileError) as error:
        parse(text, "show.toml", Path("."))
    assert message in str(error.value) and "show.toml: effects[0]" in str(error.value)
