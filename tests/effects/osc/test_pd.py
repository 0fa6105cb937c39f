"""Pure Data (headless, the shipped patch) receives what the effect sends and echoes it back."""
import pytest

from host import Side
from tests.effects.osc.helpers import Script, as_sent, hand_at, make_osc, run_show

GESTURE_TEMPLATE = {"on": "gesture", "address": "/issv/gesture", "args": ["{name}", "{complete}", 2**40, "{t}"]}


def test_pd_receives_every_frame_hand_and_gesture(pd, receiver):
    """Whatever the effect sent (also sent to a plain socket, for reference), Pd echoes back."""
    run_show([make_osc(destinations=[pd.address, receiver.address])], realtime=True, script=Script(n=20))
    assert receiver.wait_for(lambda r: r.has_frame(20))
    sent = receiver.messages()
    echo = pd.echo
    assert echo.wait_for(lambda r: len(r.messages()) == len(sent) + 1)  # and /echo/ready
    for (address, _, args), (echoed, _, back) in zip(sent, echo.messages()[1:]):
        assert echoed == address.replace("/issv/", "/echo/")
        assert list(back) == as_sent(args)  # Pd keeps 32-bit floats: the values round-trip
    hands = echo.messages("/echo/hand")
    assert len(hands) >= 30  # newest wins: a loaded machine may skip a frame, never a gesture
    for (_, _, (_, t, _)), (_, _, (hand_id, side, state, x, y, z, confidence)) in zip(
            [m for m in echo.messages("/echo/frame") for _ in range(2)], hands):
        assert hand_id == {"left": 1, "right": 2}[side] and confidence == 1.0 and state in ("new", "tracking")
        assert [x, y, z] == pytest.approx(hand_at(Side(side), round(t * 30)), rel=1e-6)
    assert [m[2][:4] for m in echo.messages("/echo/gesture")] == [
        ["wave", "complete", "right", 2.0], ["swipe_left", "complete", "left", 1.0]]
    assert "error" not in pd.close()


def test_pd_safe_makes_true_and_int64_readable_by_pd(pd):
    run_show([make_osc(destinations=[pd.address], scheme="custom", messages=[GESTURE_TEMPLATE])],
             realtime=True, script=Script(n=12))
    assert pd.echo.wait_for(lambda r: r.messages("/echo/gesture"))
    assert pd.echo.messages("/echo/gesture")[0][2] == ["wave", 1.0, float(2**40), pytest.approx(9 / 30)]
    assert "oscparse" not in pd.close()  # (the patch's display may complain: this is not the default scheme)


def test_without_pd_safe_pd_rejects_the_types(pd):
    run_show([make_osc(destinations=[pd.address], scheme="custom", pd_safe=False, messages=[GESTURE_TEMPLATE])],
             realtime=True, script=Script(n=12))
    assert pd.echo.wait_for(lambda r: r.messages("/echo/gesture"))
    args = pd.echo.messages("/echo/gesture")[0][2]
    assert args[0] == "wave" and float(2**40) not in args  # oscparse gave up at the T
    assert "oscparse: unknown tag 'T'" in pd.close()
