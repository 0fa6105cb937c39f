"""Examples as issv learn reads them: here a depth clip, tracked by the open engine."""
from host.learned.examples import read_take
from host.learned.learner import learn
from tests.backends.engine.performer import frames, idle, write_clip


def test_a_depth_clip_is_tracked_and_its_repetitions_learned(tmp_path):
    steps = [idle(1.0)] + [s for _ in range(3) for s in ({"action": "click"}, idle(1.2))]
    clip = write_clip(tmp_path / "pushes.npz", frames(steps, background="none"))
    take = read_take(f"{clip}@0-", True)  # the window form too, as an artist cuts a take
    gesture = learn("push", [take])
    assert take.source == f"{clip}@0-"
    assert len(gesture.repetitions) == 3 and gesture.hands == "right"  # three pushes of the right hand
