"""The default scheme as receivers see it: oscdump's decoding and a raw UDP socket."""
import re

import pytest

from effects.osc.schema import SCHEMA_TEXT
from host import Side, TruthGesture
from tests.effects.osc.helpers import FPS, Script, hand_at, make_osc, run_show

DOCUMENTED = {address: types.replace(" ", "") for address, types in
              re.findall(r"^\s+(/issv/\w+)\s+((?:[ifs] )*[ifs])\s\s", SCHEMA_TEXT, re.M)}


def test_the_documented_addresses_are_parsed_from_the_schema():
    assert DOCUMENTED == {"/issv/frame": "ifi", "/issv/hand": "issffff", "/issv/gesture": "sssiffff"}


def test_oscdump_decodes_bundles_with_exactly_the_documented_types(oscdump):
    run_show([make_osc(destinations=[oscdump.address])], realtime=True, script=Script(n=20))
    lines = oscdump.stop(expect=3 * 20 + 2)
    assert {line[1] for line in lines} == set(DOCUMENTED)
    for line in lines:
        assert line[2] == DOCUMENTED[line[1]], line
    frames = [line for line in lines if line[1] == "/issv/frame"]
    seqs = [int(line[3]) for line in frames]
    assert seqs == sorted(set(seqs)) and seqs[-1] == 20 and len(seqs) >= 15  # newest wins, in order
    for frame in frames:  # each frame's messages share the bundle's time tag
        same = [line for line in lines if line[0] == frame[0]]
        assert [line[1] for line in same] == ["/issv/frame", "/issv/hand", "/issv/hand"]
    names = [line[3] for line in lines if line[1] == "/issv/gesture"]
    assert names == ['"wave"', '"swipe_left"']


def test_hand_values_are_the_performers_positions_in_mm(receiver):
    run_show([make_osc(destinations=[receiver.address])])
    assert receiver.wait_for(lambda r: r.has_frame(30))
    bundles = [p for p in receiver.packets if p.bundle]
    assert bundles
    for packet in bundles:
        (address, _, (seq, t, count)), *hands = packet.messages
        assert address == "/issv/frame" and count == len(hands) == 2
        i = round(t * FPS)
        assert seq == i + 1
        for _, _, (hand_id, side, state, x, y, z, confidence) in hands:
            assert state in ("new", "tracking") and confidence == 1.0
            assert (x, y, z) == pytest.approx(hand_at(Side(side), i), rel=1e-6)


def test_each_gesture_is_its_own_datagram_sent_before_its_frames_bundle(receiver):
    run_show([make_osc(destinations=[receiver.address])], realtime=True, script=Script(n=20))
    assert receiver.wait_for(lambda r: r.has_frame(20))
    order = []
    for packet in receiver.packets:
        if not packet.bundle:
            assert len(packet.messages) == 1 and packet.messages[0][0] == "/issv/gesture"
            order.append(("gesture", packet.messages[0][2][0]))
        else:
            order.append(("frame", packet.messages[0][2][0]))
    # the wave ends at frame index 9 (seq 10), the swipe at index 18 (seq 19): each goes out just
    # before the first bundle of a frame at or after the one that ended it
    for name, seq in (("wave", 10), ("swipe_left", 19)):
        k = order.index(("gesture", name))
        assert order[k + 1][0] == "frame" and order[k + 1][1] >= seq
        assert all(o[1] < seq for o in order[:k] if o[0] == "frame")
    wave = receiver.messages("/issv/gesture")[0][2]
    assert wave[:4] == ["wave", "complete", "right", 2]
    assert wave[4:7] == pytest.approx(hand_at(Side.RIGHT, 9), rel=1e-6)


def test_a_hand_that_goes_is_sent_once_as_absent(receiver):
    script = Script(n=12, hands=lambda i: (Side.LEFT, Side.RIGHT) if i < 6 else (Side.RIGHT,), gestures=())
    run_show([make_osc(destinations=[receiver.address])], realtime=True, script=script)
    assert receiver.wait_for(lambda r: r.has_frame(12))
    states = [m[2][2] for m in receiver.messages("/issv/hand") if m[2][1] == "left"]
    assert states[-1] == "absent" and set(states[:-1]) <= {"new", "tracking"} and len(states) > 3
    counts = [m[2][2] for m in receiver.messages("/issv/frame")]
    assert counts == sorted(counts, reverse=True) and counts[0] == 2 and counts[-1] == 1


def test_filters_prefix_and_in_progress(receiver):
    effect = make_osc(destinations=[receiver.address], hands=["right"], gestures=["wave"], in_progress=True,
                      prefix="/stage/a")
    script = Script(gestures=(TruthGesture("wave", Side.RIGHT, 5 / FPS, 9 / FPS),
                              TruthGesture("wave", Side.LEFT, 12 / FPS, 14 / FPS),
                              TruthGesture("click", Side.RIGHT, 20 / FPS, 22 / FPS)))
    run_show([effect], script=script)
    assert receiver.wait_for(lambda r: r.has_frame(30, "/stage/a/frame"))
    assert receiver.messages("/issv/frame") == []
    assert {m[2][1] for m in receiver.messages("/stage/a/hand")} == {"right"}
    assert [m[2][:3] for m in receiver.messages("/stage/a/gesture")] == [
        ["wave", "in_progress", "right"], ["wave", "complete", "right"]]


def test_rate_limit_thins_hand_bundles_but_never_gestures(receiver):
    run_show([make_osc(destinations=[receiver.address], rate=10)], realtime=True, script=Script(n=30))
    assert receiver.wait_for(lambda r: len(r.messages("/issv/gesture")) == 2)
    assert 7 <= len(receiver.messages("/issv/frame")) <= 12  # 1 s at 30 Hz, limited to 10 a second
