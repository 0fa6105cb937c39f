"""Examples as issv learn reads them: here a depth clip, tracked by the open engine."""
import io
import json

import numpy as np

from host.app import plugin_class
from host.assemble import make_backend
from host.commands.track import track
from host.contracts import frames_of
from host.learned.examples import read_take
from host.learned.features import performer_body, postures
from host.learned.learner import learn
from host.model import Gesture
from host.plugins import default_registry
from host.profile import parse
from tests.backends.engine.performer import frames, idle, write_clip


def test_a_depth_clip_is_tracked_and_its_repetitions_learned(tmp_path):
    steps = [idle(1.0)] + [s for _ in range(3) for s in ({"action": "click"}, idle(1.2))]
    clip = write_clip(tmp_path / "pushes.npz", frames(steps, background="none"))
    take = read_take(f"{clip}@0-", True)  # the window form too, as an artist cuts a take
    gesture = learn("push", [take])
    assert take.source == f"{clip}@0-"
    assert len(gesture.repetitions) == 3 and gesture.hands == "right"  # three pushes of the right hand


def test_a_depth_clip_is_measured_against_the_performers_own_torso_and_head(tmp_path):
    """As the show measures each user's hands (host/learned_users.py), not against a torso guessed
    from the hands: the open engine reports its performer's skeleton."""
    steps = [idle(1.0), {"action": "hand_raise"}, idle(1.0)]
    clip = write_clip(tmp_path / "raise.npz", frames(steps, background="none"))
    source_cls, backend_cls = plugin_class("sources", "clip"), plugin_class("backends", "openiss")
    body, guessed = [], []
    with backend_cls(source_cls(source_cls.Options(path=str(clip))), backend_cls.Options()) as tracker:
        while (frame := tracker.update()) is not None:
            body.append((frame.timestamp, frame.hands, performer_body(frame)))
            guessed.append((frame.timestamp, frame.hands, {}))
    assert all("torso" in points and "head" in points for _, _, points in body[5:])  # the engine's skeleton
    take = read_take(str(clip), True)
    assert np.allclose(take.postures, postures(body, True)[1])
    assert not np.allclose(take.postures, postures(guessed, True)[1], atol=0.05)


def test_track_learned_recognises_a_clip_as_the_show_does(tmp_path):
    """`issv track --learned` and `issv run` (host.assemble.make_backend) give the same learned
    events on the same clip: both measure each user's hands against their own torso and head."""
    teach = [idle(1.0)] + [s for _ in range(3) for s in ({"action": "click"}, idle(1.2))]
    learn("push", [read_take(str(write_clip(tmp_path / "teach.npz", frames(teach, background="none"))), True)]) \
        .save(tmp_path / "push.gesture.json")
    show = [idle(1.0), {"action": "click"}, idle(1.0), {"action": "wave"}, {"action": "click"}, idle(1.0)]
    clip = write_clip(tmp_path / "show.npz", frames(show, seed=7, background="none"))
    out = io.StringIO()
    track(clip, plugin_class("backends", "openiss"), plugin_class("sources", "clip"), None, out,
          [tmp_path / "push.gesture.json"])
    tracked = [(e["name"], e["state"], e["hand"]) for e in map(json.loads, out.getvalue().splitlines())
               if e.get("native") == "learned"]
    profile = parse(f'[source]\nname = "clip"\npath = "{clip}"\n[backend]\nname = "openiss"\n'
                    f'learned = ["push.gesture.json"]\n', "show.toml", tmp_path, default_registry())
    backend = make_backend(profile, realtime=False)
    backend.init()  # as the frame loop starts a backend
    backend.start_hand_tracking()
    backend.start_gesture_detection()
    try:
        shown = [(e["name"], e["state"], e["hand"]) for frame in frames_of(backend)
                 for e in map(Gesture.to_json, frame.gestures) if e.get("native") == "learned"]
    finally:
        backend.stop()
    assert tracked == shown and tracked.count(("push", "complete", 12)) == 2  # both pushes, user 1's right hand
