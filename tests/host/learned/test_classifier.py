"""The classifier that vetoes the template matcher's confusions (host/learned/classifier.py)."""
from __future__ import annotations

import numpy as np

from host.learned.classifier import Classifier, Describer, describe_all
from host.learned.examples import read_take
from host.learned.segment import find_repetitions
from tests.host.learned.performer import Performer, circle, punch


def _repetitions(tmp_path, motion, performer: Performer) -> list[np.ndarray]:
    csv = tmp_path / f"{motion.__name__}_{performer.seed}.csv"
    performer.write(csv, motion, 4)
    take = read_take(str(csv), True)
    return [take.postures[r.start:r.end] for r in find_repetitions(take.t, take.postures)]


def test_live_descriptors_are_the_ones_it_was_trained_on():
    postures = np.cumsum(np.random.default_rng(0).normal(0.0, 0.05, (120, 6)), axis=0)
    describer = Describer()
    live = np.array([describer.push(p) for p in postures])
    assert np.allclose(live, describe_all(postures))
    describer.reset()  # a broken stream starts again from the next posture, as a repetition does
    assert np.allclose([describer.push(p) for p in postures[50:]], describe_all(postures[50:]))
    slow = Describer(pace=2)  # a motion twice as slow, read at its own pace: every other posture
    live = np.array([slow.push(p) for p in postures])
    full = slice(61, None, 2)  # once its history holds twice as many postures as the window reads
    assert np.allclose(live[full], describe_all(postures[1::2])[30:])
    assert not np.allclose(live[full], describe_all(postures)[full])


def test_it_tells_the_loaded_gestures_and_rest_apart_for_another_performer(tmp_path):
    taught = [_repetitions(tmp_path, m, Performer(seed=1)) for m in (circle, punch)]
    classifier = Classifier.train(taught)
    for g, motion in enumerate((circle, punch)):
        for rep in _repetitions(tmp_path, motion, Performer(size_mm=600.0, speed=1.3, seed=9)):
            p = classifier.probabilities(describe_all(rep))
            assert p.shape == (len(rep), 3)
            late = p[int(0.75 * len(rep))]
            assert late.argmax() == g and late[g] > 0.9, late
            assert p[0].argmax() == 2  # the rest before it: none


def test_the_same_motion_well_away_from_where_it_was_taught_is_none(tmp_path):
    """Hands rolling above the head are not the rolling taught in front of the chest: a linear
    classifier alone would call them the circle all the more (further along the same direction);
    the repetitions moved beyond the teachers' variety, trained as "none", bound it."""
    taught = [_repetitions(tmp_path, m, Performer(seed=1)) for m in (circle, punch)]
    classifier = Classifier.train(taught)
    for rep in _repetitions(tmp_path, circle, Performer(size_mm=600.0, seed=9)):
        late = int(0.75 * len(rep))
        assert classifier.probabilities(describe_all(rep))[late].argmax() == 0
        above = rep + np.array([0.0, 0.7, 0.0] * 2)  # the whole motion higher: over the head
        assert classifier.probabilities(describe_all(above))[late][0] < 0.5


def test_the_same_motion_with_the_arms_held_wide_is_none(tmp_path):
    """Arms held out to the sides are not a gesture taught with the hands in front (MSRC-12: lifting
    the outstretched arms fired beat_both): the repetitions with the hands further apart are "none"."""
    taught = [_repetitions(tmp_path, m, Performer(seed=1)) for m in (circle, punch)]
    classifier = Classifier.train(taught)
    for rep in _repetitions(tmp_path, circle, Performer(size_mm=600.0, seed=9)):
        late = int(0.75 * len(rep))
        wide = rep + np.array([-0.6, 0.0, 0.0, 0.6, 0.0, 0.0])
        assert classifier.probabilities(describe_all(wide))[late][0] < 0.5
