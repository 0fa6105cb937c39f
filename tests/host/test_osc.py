"""Typed arguments and Pure Data type safety, checked by decoding the bytes that would be sent."""
import pytest

from host.osc import Message, encode, encode_bundle, pd_safe, placeholders, typed
from tests.effects.osc.helpers import decode


def test_python_values_get_their_natural_osc_types():
    assert [typed(v)[0] for v in (1, 2**40, 1.5, "a", True, False, None)] == list("ihfsTFN")


def test_pd_safe_leaves_only_i_f_s_and_keeps_the_values():
    message = Message("/x", (typed(True), typed(False), typed(None), typed(2**40), typed(7), ("h", 5), ("d", 0.25)))
    bundled, [(address, tags, params)] = decode(encode(message, pd=True))
    assert not bundled and address == "/x"
    assert tags == "iisfiif"
    assert params == [1, 0, "nil", float(2**40), 7, 5, 0.25]


def test_without_pd_safe_the_types_go_out_unchanged():
    message = Message("/x", (typed(True), typed(2**40), ("d", 0.25)))
    _, [(_, tags, params)] = decode(encode(message, pd=False))
    assert tags == "Thd" and params == [True, 2**40, 0.25]


def test_a_bundle_holds_the_messages_in_order():
    bundled, messages = decode(encode_bundle([Message("/a", (("i", 1),)), Message("/b", (("s", "x"),))], pd=True))
    assert bundled and messages == [("/a", "i", [1]), ("/b", "s", ["x"])]
    assert pd_safe(("f", 1.0)) == ("f", 1.0)


def test_the_bytes_are_what_python_osc_would_build():
    from pythonosc.osc_bundle_builder import IMMEDIATELY, OscBundleBuilder
    from pythonosc.osc_message_builder import OscMessageBuilder

    message = Message("/issv/hand", (("i", -3), ("s", "droite é"), ("f", 1.25), ("T", True), ("h", 2**40),
                                     ("d", 0.1), ("N", None), ("F", False)))
    builder = OscMessageBuilder(message.address)
    for tag, value in message.args:
        builder.add_arg(value, tag)
    assert encode(message, pd=False) == builder.build().dgram
    bundle = OscBundleBuilder(IMMEDIATELY)
    bundle.add_content(builder.build())
    bundle.add_content(builder.build())
    assert encode_bundle([message, message], pd=False) == bundle.build().dgram


def test_template_placeholders_are_the_format_fields_and_a_stray_brace_is_named():
    assert placeholders("/{side}/xyz {x_mm}{{literal}}") == ["side", "x_mm"]
    with pytest.raises(ValueError, match=r"'/\{side/xyz'.*write \{\{ and \}\} for literal braces"):
        placeholders("/{side/xyz")
