"""Issue 18: "a performer walking, or doing something else, triggers nothing", on real skeletons of
people who never taught anything: the six MSRC-12 gestures of the judged protocol, taught by p01-p03,
while Kinder-Gator's adults and children walk, run and raise a hand (needs ISSV_DATA)."""
from __future__ import annotations

import json
from pathlib import Path

from host import GestureState
from host.commands.gestures import read_trajectories
from host.learned.examples import read_take
from host.learned.learner import counter_example, learn
from host.learned.recognizer import LearnedRecognizer
from tests.conftest import real_data

SIX = ("goggles", "wind_it_up", "shoot", "throw", "change_weapon", "beat_both")
TEACHERS = ("p01", "p02", "p03")


def taught(unlike: dict[str, list[Path]] | None = None) -> list:
    """The six, learned from p01-p03's whole recordings; `unlike`: counter-examples per gesture."""
    msrc, out = real_data("msrc12-dev"), []
    for name in SIX:
        takes = sorted(msrc.glob(f"p0[123]_g*_{name}_*.csv"))
        assert {c.name[:3] for c in takes} == set(TEACHERS), takes
        others = [counter_example(read_take(str(c), True)) for c in (unlike or {}).get(name, [])]
        out.append(learn(name, [read_take(str(take), True) for take in takes], unlike=others))
    return out


def motions(*starts: str) -> list[Path]:
    """Kinder-Gator motions whose instruction starts with one of `starts`."""
    kinder = real_data("kinder-gator-dev")
    return [c for c in sorted(kinder.glob("*.csv"))
            if json.loads((kinder / "truth" / f"{c.stem}.json").read_text())["motion"].lower().startswith(starts)]


def completed(gestures: list, csv: Path) -> list[tuple[float, str]]:
    recognizer = LearnedRecognizer(gestures, True)
    return [(e.timestamp, e.name) for f in read_trajectories(csv) for e in recognizer.update(f.t, f.hands, f.body)
            if e.state is GestureState.COMPLETE]


def test_gestures_taught_by_msrc12_people_stay_quiet_while_adults_and_children_walk_and_run():
    walks = motions("walk", "run")
    assert len({c.name.split("_")[1] for c in walks}) == 6, "walks and runs of all six people"
    gestures = taught()
    fired = {csv.name: events for csv in walks if (events := completed(gestures, csv))}
    assert not fired, f"learned gestures while walking or running: {fired}"


def test_one_adults_raised_hands_taught_as_counter_examples_keep_the_throw_off_everyone_elses():
    """Throw's teachers hold the hand up in front after throwing: without counter-examples the throw
    completes on raised hands (MSRC-12 has no such instance to say so; bench.learned counts it on
    Kinder-Gator). Taught with p604's two takes of a raised hand as `--unlike`, it is taken for at
    most one of the other five people's ten (a child's slow raise matches a throw at half pace:
    p595's, since repetitions are also matched so), against five or more without, and MSRC-12 p04's
    throws are still found."""
    raises = motions("raise")
    mine = [c for c in raises if "_p604_" in c.name]
    others = [c for c in raises if c not in mine]
    assert len(others) == 10
    plain, gestures = taught(), taught({"throw": mine})
    assert sum(bool(completed(plain, csv)) for csv in others) >= 5
    fired = {csv.name: events for csv in others if (events := completed(gestures, csv))}
    assert len(fired) <= 1, f"learned gestures on raised hands: {fired}"
    throws = real_data("msrc12-dev", "p04_g08_throw_1.csv")
    tags = json.loads(real_data("msrc12-dev", "truth", "p04_g08_throw_1.json").read_text())["tags_s"]
    done = [t for t, name in completed(gestures, throws) if name == "throw"]
    found = [tau for tau in tags if any(tau - 1.5 <= t <= tau + 1.0 for t in done)]
    assert len(found) >= 0.9 * len(tags), (found, tags)
