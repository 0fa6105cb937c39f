"""The loop check (host/learned/loops.py): a gesture taught as a loop completes only on a loop."""
from __future__ import annotations

import numpy as np

from host.learned.classifier import Classifier, describe_all
from host.learned.gesture_file import LearnedGesture, TaughtRepetition
from host.learned.loops import AS_MUCH, WINDOW, LoopCheck, closed_loopiness, loopiness
from host.learned.matcher import CLOSE, HOLD, Matcher
from tests.host.learned.performer import REST, circle, punch


def _repetition(motion, n: int = 25) -> np.ndarray:
    """One repetition at 15 Hz as postures (n, 6): left x y z, right x y z."""
    return np.array([motion(u).ravel() for u in np.linspace(0.0, 1.0, n)])


def _rolling(turns: float, n: int = WINDOW) -> np.ndarray:
    """Hands rolling round each other in front of the chest, `turns` times (negative: the other way)."""
    a = 2 * np.pi * turns * np.linspace(0.0, 1.0, n)
    left = np.column_stack([-0.15 + 0.2 * np.cos(a), 0.1 + 0.2 * np.sin(a), np.full(n, -0.6)])
    right = np.column_stack([0.15 - 0.2 * np.cos(a), 0.1 - 0.2 * np.sin(a), np.full(n, -0.6)])
    return np.hstack([left, right])


ROLLS = [_rolling(4 / 3, 25)] * 3  # taught: hands rolling round each other, once round where it completes


def _gesture(hands: str, loop: float | None = None, motion=None, name: str = "g") -> LearnedGesture:
    """A learned gesture; with `motion`, taught by three repetitions of it."""
    reps = [TaughtRepetition("take", 0.0, 1.6, _repetition(motion)) for _ in range(3)] if motion else []
    return LearnedGesture(name, hands, 0.5, 0.75, np.ones(6), reps, loop=loop)


def test_loopiness_is_near_one_for_a_circle_either_way_round_and_zero_for_a_line():
    once = loopiness(_rolling(1.0))
    assert 0.8 < once[0] < 1.1 and 0.8 < once[3] < 1.1  # each hand, x-y: its own circle once round
    assert np.allclose(loopiness(_rolling(-1.0)), once)
    line = _rolling(1.0)
    line[:, [1, 4]] = 0.1  # the same sideways motion without the rise: back and forth
    assert np.all(loopiness(line) < 0.05)


def _arc(n: int = 25) -> np.ndarray:
    """Both hands brought up to the eyes along half a circle, side on (y-z), and held there."""
    a = np.pi * np.clip(np.linspace(0.0, 1.3, n), 0.0, 1.0)
    hand = np.column_stack([np.zeros(n), -0.35 * np.cos(a) + 0.3, -0.4 - 0.35 * np.sin(a)])
    return np.hstack([hand + [-0.1, 0.0, 0.0], hand + [0.1, 0.0, 0.0]])


def test_an_arc_sweeps_round_as_much_as_a_loop_but_does_not_go_round():
    assert loopiness(_arc()[:19])[1] > 0.45  # sweeping round its centre, a half circle is a loop of sorts
    assert closed_loopiness(_arc()[:19])[1] == 0.0  # that the hand never comes back round
    assert closed_loopiness(_rolling(1.0))[0] > 0.8  # the roll does
    check = LoopCheck([_gesture("both")], [[_arc()] * 3])
    assert not check.checked[0]  # so a performer bringing the hands straight up is not held to the arc


def test_a_gesture_taught_as_a_loop_asks_for_one_and_a_punch_asks_nothing():
    check = LoopCheck([_gesture("both"), _gesture("right")],
                      [ROLLS, [_repetition(punch)] * 3])
    assert check.taught[0, 0] > 0.45 and "left hand x-y" in check.describe(0)  # the circle, where it rolls
    assert not check.taught[1].any() and check.describe(1) == ""  # out and back the same way: no loop
    still = np.zeros((WINDOW, 6))
    sideways = _rolling(1.0)
    sideways[:, [1, 4]] = 0.1
    for motion, expected in ((_rolling(1.0), [True, True]), (_rolling(-1.0), [True, True]),
                             (still, [False, True]), (sideways, [False, True]),
                             (_rolling(1.0)[:3], [False, True])):  # too little seen to tell
        assert list(check.passes(lambda g: motion)) == expected


def test_one_looping_hand_is_enough_and_a_profile_may_turn_the_check_off():
    reps = [ROLLS]
    one_arm = _rolling(1.0)
    one_arm[:, 3:] = REST[1]  # the right hand hangs at rest
    assert LoopCheck([_gesture("both")], reps).passes(lambda g: one_arm)[0]
    line = np.zeros((WINDOW, 6))
    line[:, 0] = np.linspace(-0.3, 0.3, WINDOW)
    assert not LoopCheck([_gesture("both")], reps).passes(lambda g: line)[0]
    assert LoopCheck([_gesture("both", loop=0.0)], reps).passes(lambda g: line)[0]


def test_hands_half_way_round_do_not_complete_a_loop_yet():
    """Half a turn sweeps round its centre as much as a loop does (loopiness), but has not gone round:
    a slow performer's big circle matched that far is not complete until the hands come back."""
    check = LoopCheck([_gesture("both")], [ROLLS])
    half = _rolling(0.5)
    assert loopiness(half)[0] > AS_MUCH  # what the check read before
    assert not check.passes(lambda g: half)[0]
    assert check.passes(lambda g: _rolling(1.0))[0]


def test_a_loop_found_at_one_of_the_postures_held_completes_and_none_found_does_not():
    """Templates and classifier must agree for HOLD postures running; where the loop closes moves
    as the match goes on, so the check may pass at one of them only (MSRC-12 p04's high, wide
    circles passed it at one or two postures of three and were missed). Without it at any, nothing."""
    roll = _gesture("both", motion=circle, name="roll")
    near, agree = np.array([0.1]), np.array([1.0])  # a template well below the threshold, the classifier sure
    for looped_at, completes in ((1, True), (None, False)):
        matcher = Matcher([roll], classify=False, one_arm=False)
        assert matcher.loops.checked[0]
        done = [any(m.complete for m in matcher._decide(near, np.array([i == looped_at]), agree, agree))
                for i in range(HOLD + 2)]
        assert done == ([False] * (HOLD - 1) + [True, False, False] if completes else [False] * (HOLD + 2))


def _always(probabilities: list[float]) -> Classifier:
    """A classifier that gives these probabilities (gestures, then "none") whatever it is shown."""
    size = describe_all(np.zeros((1, 6))).shape[1]
    return Classifier(np.zeros(size), np.ones(size), np.zeros((2 * size, len(probabilities))), np.log(probabilities))


def test_a_close_roll_the_classifier_takes_for_a_beat_completes_where_its_loop_is_found():
    """MSRC-12 p06 winds slow, wide circles that the classifier takes for beat_both (0.95-0.97,
    wind_it_up under CLOSE) while a wind_it_up template is close and the loop is found. A beat does
    not loop: the loop tells them apart, so among the looping gestures and "none" the roll is not
    ruled out where the loop is found, at each of the postures held (a classifier sure of the roll
    needs it at one of them: the test above). Without the loop, or where the classifier sees rest
    ("none"), nothing completes."""
    roll = _gesture("both", motion=circle, name="roll")
    beat = _gesture("right", motion=punch, name="beat")  # out and back the same way: no loop
    near = np.array([0.1, np.inf])  # the roll's template well within "close"
    confused, rest = [0.01, 0.97, 0.02], [0.001, 0.001, 0.998]
    once = [True] + [False] * (HOLD - 1)
    for probabilities, looped, completes in ((confused, [True] * HOLD, True), (confused, once, False),
                                             (confused, [False] * HOLD, False), (rest, [True] * HOLD, False)):
        matcher = Matcher([roll, beat], classifier=_always(probabilities), one_arm=False)
        assert matcher.loops.checked.tolist() == [True, False]
        agree, among_loops = matcher._agree(REST.ravel())
        assert agree[0] < CLOSE and among_loops[1] == 0.0  # the beat is not a looping gesture
        assert np.isclose(among_loops[0], probabilities[0] / (probabilities[0] + probabilities[2]))
        done = [any(m.complete for m in matcher._decide(near, np.array([found, True]), agree, among_loops))
                for found in looped]
        assert done == [False] * (HOLD - 1) + [completes]


def _turned(postures: np.ndarray, degrees: float) -> np.ndarray:
    """Each hand's path about its centre turned `degrees` about the x axis (towards lying flat, x-z)."""
    a = np.radians(degrees)
    out = postures.copy()
    for hand in (slice(0, 3), slice(3, 6)):
        p = postures[:, hand] - postures[:, hand].mean(axis=0)
        out[:, hand.start + 1] = p[:, 1] * np.cos(a) - p[:, 2] * np.sin(a) + postures[:, hand.start + 1].mean()
        out[:, hand.start + 2] = p[:, 1] * np.sin(a) + p[:, 2] * np.cos(a) + postures[:, hand.start + 2].mean()
    return out


def test_a_loop_must_face_the_way_the_taught_loops_did():
    """Taught rolling in front (x-y, facing the camera), leaning 0 to 20 degrees towards lying flat, a
    loop leaning up to 45 degrees from their 10 is the gesture (three teachers alike say little of
    everyone: no tighter than that); one leaning further towards lying flat (x-z, facing up: a hand
    pushed out to the side and brought back lower, MSRC-12's push_right) is not. The areas are
    unsigned: leaning either way is the same."""
    taught = [_turned(ROLLS[0], degrees) for degrees in (0, 10, 20)]
    check = LoopCheck([_gesture("both")], [taught])
    ten = np.radians(10)
    assert np.allclose(check.faces[0], [np.cos(ten), 0.0, np.sin(ten)], atol=1e-3)
    assert np.isclose(check.tilt[0], np.cos(np.radians(45)), atol=1e-3)
    for degrees, passes in ((5, True), (40, True), (-25, True), (0, True), (60, False), (90, False)):
        assert check.passes(lambda g: _turned(_rolling(1.0), degrees))[0] == passes, degrees


def test_a_roll_taught_with_both_hands_is_matched_on_one_arm_as_big_as_a_taught_hand():
    """MSRC-12's teachers wind it up with both hands; p07 rolls the right arm alone, p09 swings one arm
    at a time in a big circle. The two-handed form's templates are far from either; a form of the
    gesture on each arm alone, the other hanging where it began, matches them. Its loop must be at
    least as big as a taught hand's: a smaller one-hand loop is a hand moving, not a roll."""
    roll = _gesture("both", motion=circle, name="roll")
    matcher = Matcher([roll], classify=False)
    assert [f.hands for f in matcher.forms] == ["both", "left", "right"]
    assert matcher.gesture_of_form.tolist() == [0, 0, 0]
    left_alone = int(np.flatnonzero([f.hands == "left" for f in matcher.forms])[0])
    assert matcher.loops.checked[left_alone] and matcher.loops.least[0] == 0.0  # two hands: no size asked
    one_arm = _repetition(circle)
    one_arm[:, 3:] = REST[1]  # the right hand hangs at rest
    big = one_arm[:roll.completes_at(len(one_arm))]  # what a template matches, up to where it completes
    small = big.copy()
    small[:, :3] = big[:, :3].mean(axis=0) + 0.5 * (big[:, :3] - big[:, :3].mean(axis=0))
    assert matcher.loops.passes(lambda f: big)[left_alone]
    assert not matcher.loops.passes(lambda f: small)[left_alone]  # a quarter of the taught hand's loop

    def completions(matcher: Matcher, postures: np.ndarray) -> list[tuple[int, bool, str]]:
        """(gesture, complete, the hands of the form it was found in) for each match."""
        return [(m.index, m.complete, matcher.forms[m.form].hands) for p in postures for m in matcher.update(p)]

    three = np.concatenate([one_arm] * 3)
    found = completions(Matcher([roll], classify=False), three)
    assert (0, True, "left") in found  # the event is the left arm's (recognizer.py)
    assert found.count((0, False, "left")) == found.count((0, True, "left"))  # one IN_PROGRESS each
    assert completions(Matcher([roll], classify=False, one_arm=False), three) == []
