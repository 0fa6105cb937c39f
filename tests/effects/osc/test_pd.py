"""Pure Data (headless, the shipped patch) receives what the effect sends and echoes it back."""
import pytest

from host import Side
from tests.effects.osc.helpers import Script, hand_at, make_osc, run_show

GESTURE_TEMPLATE = {"on": "gesture", "address": "/issv/gesture", "args": ["{name}", "{complete}", 2**40, "{t}"]}


def test_pd_receives_every_frame_hand_and_gesture(pd):
    run_show([make_osc(destinations=[pd.address])], realtime=True, script=Script(n=20))
    echo = pd.echo
    assert echo.wait_for(lambda r: len(r.messages("/echo/frame")) == 20 and len(r.messages("/echo/gesture")) == 2)
    assert [m[2][0] for m in echo.messages("/echo/frame")] == list(range(1, 21))
    hands = echo.messages("/echo/hand")
    assert len(hands) == 40
    for k, (_, _, (hand_id, side, state, x, y, z, confidence)) in enumerate(hands):
        assert hand_id == {"left": 1, "right": 2}[side] and confidence == 1.0
        assert state == ("new" if k < 2 else "tracking")
        assert [x, y, z] == pytest.approx(hand_at(Side(side), k // 2), rel=1e-6)
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
