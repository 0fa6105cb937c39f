"""Each bridge's messages read back into users and joints in millimetres."""
import pytest

from backends.oscin.schemes import (BadMessage, CustomScheme, InputTemplate, KinectV2Scheme, MediaPipeScheme,
                                    NiMateScheme, OSCeletonScheme, Reading, SynapseScheme, UserEvent)
from effects.osc.coords import Projector
from effects.osc.osceleton import OSCeletonScheme as OSCeletonOut
from effects.osc.synapse import SynapseScheme as SynapseOut
from host import Frame, Hand, HandState, Side


def _sent(scheme, hands):
    """What the osc effect's preset sends for these hands (mm space), as (address, values)."""
    frame = Frame(1, 0.0, None, tuple(hands))
    messages = scheme.frame(frame, list(hands), [], Projector("mm", None, (500.0, 4500.0)))
    return [(m.address, [v for _, v in m.args]) for m in messages]


HANDS = [Hand(1, HandState.TRACKING, (-312.5, 140.0, 2100.0), Side.LEFT, user_id=2),
         Hand(2, HandState.TRACKING, (410.0, -95.5, 1890.0), Side.RIGHT, user_id=2)]


def test_osceleton_reads_back_what_the_osc_effect_sends():
    scheme = OSCeletonScheme()
    readings = [r for address, args in _sent(OSCeletonOut(), HANDS) for r in scheme.read(address, args)]
    assert readings[:2] == [UserEvent(2, "new"), UserEvent(2, "new")]  # /new_user, /new_skel
    joints = {r.joint: r for r in readings[2:]}
    assert joints["left_hand"].user == 2 and joints["left_hand"].position == pytest.approx(HANDS[0].position)
    assert joints["right_hand"].position == pytest.approx(HANDS[1].position)


def test_osceleton_undoes_multiplier_and_offset():
    plain = OSCeletonScheme().read("/joint", ["head", 1, 0.6, 0.3, 2.0])[0].position
    scaled = OSCeletonScheme((5.0, 2.0, 1.0), (-0.75, 0.1, 0.0)).read(
        "/joint", ["head", 1, 0.6 * 5 - 0.75, 0.3 * 2 + 0.1, 2.0])[0].position
    assert scaled == pytest.approx(plain)
    assert plain == pytest.approx((0.1 * 2560, 960 - 0.3 * 1920, 2560.0))


def test_osceleton_kitchen_and_quartz_variants():
    scheme = OSCeletonScheme(kitchen_depth_mm=1800.0)
    (kitchen,) = scheme.read("/joint", ["l_shoulder12", 0.5, 0.5])
    assert kitchen == Reading(12, "left_shoulder", (0.0, 0.0, 1800.0))
    (quartz,) = scheme.read("/joint/r_knee/3", [0.25, 0.75, 1.5])
    assert quartz.user == 3 and quartz.joint == "right_knee"
    assert quartz.position == pytest.approx((-640.0, -480.0, 1920.0))
    assert scheme.read("/lost_user", [3]) == [UserEvent(3, "lost")]
    assert scheme.read("/joint", ["head", 4.0, 0.5, 0.5, 1.0])[0].user == 4  # Pd sends ids as floats


@pytest.mark.parametrize("address, args, kind", [
    ("/joint", ["head", "x", 0.5, 0.5, 1.0], "/joint without an integer user id"),
    ("/joint", ["head", 1, 0.5, "y", 1.0], "/joint without 3 numbers"),
    ("/joint", ["head", 1, float("nan"), 0.5, 1.0], "/joint with a non-finite number"),
    ("/joint", [1, 2], "/joint without s i f f f (or s f f)"),
    ("/joint", ["head", 0.5, 0.5], "/joint (kitchen mode) without a user number after the joint name"),
    ("/hello", [1], "unknown OSCeleton address"),
    ("/new_user", [], "/new_user without a user id"),
])
def test_osceleton_bad_messages_have_a_kind(address, args, kind):
    with pytest.raises(BadMessage) as error:
        OSCeletonScheme().read(address, args)
    assert error.value.kind == kind


def test_synapse_reads_world_positions_and_asks_for_them():
    scheme = SynapseScheme()
    readings = [r for address, args in _sent(SynapseOut(), HANDS) for r in scheme.read(address, args)]
    assert readings[0] == UserEvent(1, "new")  # /tracking_skeleton 1
    joints = {r.joint: r.position for r in readings[1:]}  # _pos_screen is Synapse's own view: not read
    assert joints == {"left_hand": pytest.approx(HANDS[0].position), "right_hand": pytest.approx(HANDS[1].position)}
    assert scheme.read("/tracking_skeleton", [0]) == [UserEvent(1, "lost")]
    assert scheme.read("/righthand", ["up"]) == []
    keepalive = dict(scheme.keepalive())
    assert keepalive["/righthand_trackjointpos"] == [2] and keepalive["/torso_trackjointpos"] == [2]
    with pytest.raises(BadMessage, match="unknown Synapse joint"):
        scheme.read("/tail_pos_world", [1.0, 2.0, 3.0])


def test_ni_mate_basic_and_osceleton_style_in_metres():
    scheme = NiMateScheme()
    assert scheme.read("/Left_Hand", [0.1, 0.2, 1.5]) == [Reading(1, "left_hand", (100.0, 200.0, 1500.0))]
    assert scheme.read("/joint", ["Right_Elbow", 2, 0.3, 0.4, 2.0]) == [
        Reading(2, "right_elbow", (300.0, 400.0, 2000.0))]
    with pytest.raises(BadMessage, match="unknown NI mate joint"):
        scheme.read("/Left_Tail", [0.0, 0.0, 0.0])


def test_kinectv2_numbers_bodies_and_reads_tracking_state():
    scheme = KinectV2Scheme()
    (hand,) = scheme.read("/bodies/72057594037931101/joints/HandLeft", [0.1, 0.2, 1.8, "Inferred"])
    assert hand == Reading(1, "left_hand", (100.0, 200.0, 1800.0), 0.5)
    assert scheme.read("/bodies/72057594037931102/joints/Head", [0.0, 0.5, 2.0, "Tracked"])[0].user == 2
    assert scheme.read("/bodies/72057594037931101/joints/Head", [0.0, 0.5, 2.0, "NotTracked"]) == []
    assert scheme.read("/bodies/72057594037931101/hands/Left", ["Open", "High"]) == []


def test_mediapipe_flat_landmark_list():
    values = []
    for i in range(33):
        values += [0.01 * i, -0.5 if i == 0 else 0.1, 0.05, 0.9]
    readings = {r.joint: r for r in MediaPipeScheme(depth_mm=2000.0).read("/pose/1", values)}
    assert readings["head"].user == 2  # bridges count people from 0
    assert readings["head"].position == pytest.approx((0.0, 500.0, 2050.0))  # y up, placed 2 m away
    assert readings["left_hand"].position[0] == pytest.approx(190.0)
    assert readings["left_hand"].confidence == pytest.approx(0.9)
    assert readings["torso"].position == pytest.approx((175.0, -100.0, 2050.0))  # shoulders and hips
    with pytest.raises(BadMessage, match="33 x 3 or 33 x 4"):
        MediaPipeScheme().read("/pose", [0.0] * 10)


def test_custom_templates_read_fields_from_address_and_arguments():
    templates = [InputTemplate(address="/skel/{user}/{joint}", args=["{x}", "{y}", "{z}"]),
                 InputTemplate(on="lost_user", address="/gone", args=["{user}"])]
    scheme = CustomScheme(templates, scale=1000.0)
    assert scheme.read("/skel/3/l_hand", [0.1, 0.2, 2.0]) == [Reading(3, "left_hand", (100.0, 200.0, 2000.0))]
    assert scheme.read("/gone", [3]) == [UserEvent(3, "lost")]
    with pytest.raises(BadMessage, match="matching no template"):
        scheme.read("/other", [])
    with pytest.raises(ValueError, match="unknown field {side}"):
        InputTemplate(address="/skel/{side}", args=["{x}", "{y}", "{z}"])
    with pytest.raises(ValueError, match="needs joint"):
        InputTemplate(address="/skel", args=["{x}", "{y}", "{z}"])


def test_positions_through_32_bit_floats_come_back_to_the_trackers_own_decimals():
    """OSCeleton's normalised floats are 32-bit: mm with 0.1 mm decimals come back as the very
    same floats (the recogniser then sees the stream as the file has it)."""
    import numpy as np
    scheme = OSCeletonScheme()
    for x, y, z in [(-314.3, -17.0, 2900.3), (85.6, -45.6, 2905.7), (1093.7, 837.4, 4087.9), (-0.1, 0.1, 800.2)]:
        sent = [float(np.float32(v)) for v in ((x + 1280) / 2560, (960 - y) / 1920, z / 1280)]
        assert sent[0] * 2560 - 1280 != x  # the wire alone does not give them back
        assert scheme.read("/joint", ["r_hand", 1, *sent])[0].position == (x, y, z)


def test_time_tags_carry_a_senders_own_times_back_exactly():
    """Stamped as a time of day, times with up to nine decimals come back as the same floats."""
    from backends.oscin.decode import midnight, seconds_since, stamp, time_tag
    origin = midnight(time_tag(1_795_000_000.25))
    assert origin == midnight(stamp(origin, 86399.9))  # every tag of the day has the same midnight
    for t in (0.6832, 1.0, 4.89804842, 29.88997152, 50.4, 3599.9999, 86399.123456789):
        assert seconds_since(origin, stamp(origin, t)) == t
