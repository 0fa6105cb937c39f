"""Learned gestures per user: two performers sent over real UDP by `issv osc-replay` to osc-in,
through the host's wrapper (host.assemble.make_backend, as `issv run` builds it)."""
from __future__ import annotations

from pathlib import Path

import pytest

from host import Frame, GestureState, GestureType, Hand, HandState, Side
from host.assemble import make_backend
from host.learned.examples import read_take
from host.learned.learner import learn
from host.learned.recognizer import LearnedRecognizer
from host.learned_users import LearnedByUser
from host.plugins import default_registry
from host.profile import parse
from tests.backends.oscin.helpers import FPS, collect, replay, write_session
from tests.host.learned.performer import Performer, circle, punch
from tests.host.test_loop import QuietBackend

APART_MM = 700.0  # user 1 stands left of the middle, user 2 right


def _performance(tmp_path: Path):
    """User 1 punches twice while user 2 rolls its hands twice, side by side, 30 Hz."""
    one, _ = Performer(seed=3).frames(punch, 2)
    two, _ = Performer(seed=5, speed=1.3).frames(circle, 2)
    frames, bodies = [], []
    for (t, p1), (_, p2) in zip(one, two):
        hands, body = [], {}
        for user, points, dx in ((1, p1, -APART_MM), (2, p2, APART_MM)):
            at = {name: (float(p[0]) + dx, float(p[1]), float(p[2])) for name, p in points.items()}
            hands += [Hand(1, HandState.TRACKING, at["left"], Side.LEFT, user),
                      Hand(2, HandState.TRACKING, at["right"], Side.RIGHT, user)]
            body[user] = {"torso": at["torso"], "head": at["head"]}
        frames.append(hands)
        bodies.append(body)
    return write_session(tmp_path / "duet.txt", frames, bodies=bodies), one


@pytest.fixture(scope="module")
def punch_file(tmp_path_factory) -> Path:
    """A punch taught by four repetitions of another performer (seed 1)."""
    take = tmp_path_factory.mktemp("punch") / "take.csv"
    Performer(seed=1).write(take, punch, 4)
    learn("punch", [read_take(str(take), True)]).save(take.with_name("punch.gesture.json"))
    return take.with_name("punch.gesture.json")


def test_each_user_of_osc_in_gets_its_own_learned_gestures(tmp_path, punch_file):
    session, alone = _performance(tmp_path)
    text = (f'[backend]\nname = "osc-in"\nport = 0\nend_after_idle_s = 0.8\nlost_timeout_s = 0.5\n'
            f'learned = ["{punch_file}"]\n')
    profile = parse(text, "show.toml", tmp_path, default_registry())
    backend = make_backend(profile, realtime=False)
    backend.init()  # as the frame loop starts a backend
    backend.start_hand_tracking()
    backend.start_gesture_detection()
    try:
        sender = replay(session, backend.port, "--time-tags")
        frames = collect(backend)
    finally:
        backend.stop()
    assert sender.wait(60) == 0, sender.stderr.read()
    learned = [g for f in frames for g in f.gestures
               if g.type is GestureType.LEARNED and g.state is GestureState.COMPLETE]
    assert [(g.name, g.user_id, g.side) for g in learned] == [("punch", 1, Side.RIGHT)] * 2  # never user 2's roll
    assert all(g.hand_id == 12 for g in learned)  # user 1's right hand
    # the same performer alone, as `issv gestures --learned` runs a file (hands, torso and head), fed the
    # samples the host saw at the times it saw them: a frame holds the newest of the samples that came
    # since the last one (how often two come together depends on the machine's load, not on the users),
    # and a sample's time is the sum of the session's millisecond steps as written, not i / FPS
    start = next(f.time for f in frames if f.users)  # the session's first joint: time 0 of the performance
    seen = {round((f.time - start) * FPS): f.time - start for f in frames if any(u.id == 1 for u in f.users)}
    assert len(seen) > 0.8 * len(alone), f"the host saw only {len(seen)} of {len(alone)} samples"
    reference = LearnedRecognizer.from_files([punch_file])
    expected = []
    for i, (_, points) in enumerate(alone):
        if i in seen:
            hands = [Hand(1, HandState.TRACKING, tuple(points["left"]), Side.LEFT),
                     Hand(2, HandState.TRACKING, tuple(points["right"]), Side.RIGHT)]
            body = {"torso": tuple(points["torso"]), "head": tuple(points["head"])}
            expected += reference.update(seen[i], hands, body)
    expected = [g for g in expected if g.state is GestureState.COMPLETE]  # each announced IN_PROGRESS first
    assert [g.name for g in expected] == ["punch", "punch"]
    assert [got.timestamp - start for got in learned] == pytest.approx([want.timestamp for want in expected], abs=1e-3)


def test_a_live_backends_nothing_yet_passes_through_to_the_frame_loop():
    """A network input with no publisher yet answers False: neither a frame nor the end."""
    backend = LearnedByUser(QuietBackend(1, first=1), [])
    answers = [backend.update() for _ in range(3)]
    assert answers[0] is False and isinstance(answers[1], Frame) and answers[2] is False


def test_a_users_recogniser_is_a_fresh_copy_of_the_first(punch_file):
    """Building a recogniser (templates, loop check) takes a few hundred milliseconds: a performer who
    walks in gets a copy of the first that shares them, with nothing seen, and recognises as a
    recogniser built anew would, whatever the first has seen."""
    alone = Performer(seed=3).frames(punch, 2)[0]

    def events(recognizer: LearnedRecognizer) -> list[tuple[str, GestureState, float]]:
        out = []
        for t, points in alone:
            hands = [Hand(1, HandState.TRACKING, tuple(points["left"]), Side.LEFT),
                     Hand(2, HandState.TRACKING, tuple(points["right"]), Side.RIGHT)]
            body = {"torso": tuple(points["torso"]), "head": tuple(points["head"])}
            out += [(g.name, g.state, round(g.timestamp, 3)) for g in recognizer.update(t, hands, body)]
        return out

    first = LearnedRecognizer.from_files([punch_file])
    anew = events(LearnedRecognizer.from_files([punch_file]))
    assert [e[:2] for e in anew].count(("punch", GestureState.COMPLETE)) == 2
    assert events(first) == anew  # the first has seen the performance
    copy = first.fresh()
    assert copy.matcher.templates is first.matcher.templates and copy.matcher.classifier is first.matcher.classifier
    assert events(copy) == anew
