"""Learned gestures reach everything a built-in gesture reaches: profiles, the host's backend
wrapper, recordings, OSC."""
from __future__ import annotations

from pathlib import Path
from typing import Literal

import pytest

from backends.truth import TruthBackend
from host import Frame, Gesture, GestureState, GestureType, Hand, HandState, Side, frames_of
from host.errors import ProfileError
from host.learned.backend import LearnedBackend
from host.learned.examples import read_take
from host.learned.learner import learn
from host.learned.recognizer import LearnedRecognizer
from host.plugins import Registry
from host.profile import parse
from host.recording import codec
from sources.clip import ClipSource
from tests.host.learned.performer import Performer, circle


@pytest.fixture(scope="module")
def roll(tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("roll")
    Performer(seed=1).write(d / "take.csv", circle, 4)
    path = d / "roll.gesture.json"
    learn("roll", [read_take(str(d / "take.csv"), True)]).save(path)
    return path


@pytest.fixture
def registry():
    r = Registry()
    r.register("backends", TruthBackend, "test")
    r.register("sources", ClipSource, "test")
    return r


def test_a_profile_names_learned_files_relative_to_itself_with_a_threshold_and_loop_of_its_own(roll, registry):
    text = f'[source]\nname = "clip"\npath = "x.npz"\n[backend]\nname = "truth"\n' \
           f'learned = ["{roll.name}", {{ file = "{roll.name}", threshold = 0.42, loop = 0 }}]\n'
    profile = parse(text, "show.toml", roll.parent, registry)
    assert [g.name for g in profile.learned] == ["roll", "roll"]
    assert profile.learned[0].threshold != 0.42 and profile.learned[1].threshold == 0.42
    assert profile.learned[0].loop is None and profile.learned[1].loop == 0  # the roll's loop check off
    assert profile.backend.options.model_dump() == TruthBackend.Options().model_dump()  # not a backend option


def test_a_missing_learned_file_is_a_profile_error_naming_the_key(registry, tmp_path):
    text = '[source]\nname = "clip"\npath = "x.npz"\n[backend]\nname = "truth"\nlearned = ["nope.gesture.json"]\n'
    with pytest.raises(ProfileError) as caught:
        parse(text, "show.toml", tmp_path, registry)
    assert any("show.toml: backend.learned[0]:" in line and "nope.gesture.json" in line for line in caught.value.lines)


class Replay:
    """A backend stand-in that replays frames of hands (as the network and replay backends do),
    each after a "nothing yet" answer (False), as a live network input gives between frames."""

    name = "replay-frames"

    def __init__(self, frames: list[Frame]) -> None:
        self.frames = iter([answer for f in frames for answer in (False, f)])

    def update(self) -> Frame | None | Literal[False]:
        return next(self.frames, None)


def test_the_host_adds_learned_gestures_to_any_backends_frames(tmp_path):
    csv = tmp_path / "show.csv"
    taught = tmp_path / "taught.csv"  # taught and shown through a tracker that reports hands only
    Performer(seed=4).write(taught, circle, 4, body=False)
    learn("roll", [read_take(str(taught), True)]).save(tmp_path / "roll.gesture.json")
    Performer(seed=3).write(csv, circle, 2, body=False)
    from host.commands.gestures import read_trajectories
    frames = []
    for seq, f in enumerate(read_trajectories(csv)):
        hands = tuple(Hand(h.id, HandState.TRACKING, h.position, h.side) for h in f.hands)
        frames.append(Frame(seq, f.t, None, hands, (), "replay-frames"))  # hands only, no body points
    backend = LearnedBackend(Replay(frames), LearnedRecognizer.from_files([tmp_path / "roll.gesture.json"]))
    seen = [g for frame in frames_of(backend) for g in frame.gestures]
    assert [(g.name, g.type, g.state) for g in seen] == [
        ("roll", GestureType.LEARNED, GestureState.IN_PROGRESS), ("roll", GestureType.LEARNED, GestureState.COMPLETE)] * 2
    assert backend.name == "replay-frames"  # everything else is the backend's own


def test_recordings_keep_a_learned_gestures_name_and_hands():
    g = Gesture(GestureType.LEARNED, GestureState.COMPLETE, (1.0, 2.0, 3.0), 0, Side.UNKNOWN, 0.8, 4.5,
                label="goggles", hands=(1, 2))
    back = codec.gesture_from_json(codec.gesture_to_json(g, 7))
    assert back == g and back.name == "goggles" and back.to_json()["native"] == "learned"
    builtin = Gesture(GestureType.WAVE, GestureState.COMPLETE, (0.0, 0.0, 1.0))
    assert builtin.name == "wave" and "hands" not in builtin.to_json()
    assert codec.gesture_from_json(codec.gesture_to_json(builtin, 1)) == builtin


def test_osc_sends_learned_gestures_unless_told_not_to():
    from effects.osc.effect import OscEffect, OscOptions
    learned = Gesture(GestureType.LEARNED, GestureState.COMPLETE, (0.0, 0.0, 2000.0), label="goggles")
    for option, expected in ((True, 1), (False, 0)):
        effect = OscEffect(OscOptions(learned=option))
        effect.projector = type("Ready", (), {"ready": True})()
        sent = []
        effect.schemes = [type("Scheme", (), {"gesture": lambda self, g, to: sent.append(g.name) or []})()]
        effect.destinations = []
        effect.on_gesture(learned)
        assert len(sent) == expected
