"""Issue 18: "a performer walking, or doing something else, triggers nothing", on real skeletons of
people who never taught anything: the six MSRC-12 gestures of the judged protocol, taught by p01-p03,
while Kinder-Gator's adults and children walk and run in place (needs ISSV_DATA)."""
from __future__ import annotations

import json

from host import GestureState
from host.commands.gestures import read_trajectories
from host.learned.examples import read_take
from host.learned.learner import learn
from host.learned.recognizer import LearnedRecognizer
from tests.conftest import real_data

SIX = ("goggles", "wind_it_up", "shoot", "throw", "change_weapon", "beat_both")
TEACHERS = ("p01", "p02", "p03")


def test_gestures_taught_by_msrc12_people_stay_quiet_while_adults_and_children_walk_and_run():
    msrc, kinder = real_data("msrc12-dev"), real_data("kinder-gator-dev")
    gestures = []
    for name in SIX:
        takes = sorted(msrc.glob(f"p0[123]_g*_{name}_*.csv"))
        assert {c.name[:3] for c in takes} == set(TEACHERS), takes
        gestures.append(learn(name, [read_take(str(take), True) for take in takes]))
    walks = [c for c in sorted(kinder.glob("*.csv"))
             if json.loads((kinder / "truth" / f"{c.stem}.json").read_text())["motion"].lower().startswith(("walk", "run"))]
    assert len({c.name.split("_")[1] for c in walks}) == 6, "walks and runs of all six people"
    fired = {}
    for csv in walks:
        recognizer = LearnedRecognizer(gestures, True)
        events = [e.name for f in read_trajectories(csv) for e in recognizer.update(f.t, f.hands, f.body)
                  if e.state is GestureState.COMPLETE]
        if events:
            fired[csv.name] = events
    assert not fired, f"learned gestures while walking or running: {fired}"
