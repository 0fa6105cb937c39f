"""Postures without body points: the torso estimated from where the hands hang at rest."""
from typing import Callable

import numpy as np

from host.learned.features import DEFAULT_SIZE_MM, REST_PLACE, PostureStream
from host.model import Hand, HandState, Side

RATE = 30.0
SIZE = DEFAULT_SIZE_MM  # no head: the stream takes an adult's size, so the truth below uses it too
HANGING = {side: np.array(REST_PLACE[side]) * SIZE for side in (Side.LEFT, Side.RIGHT)}


def at_rest(torso: np.ndarray, side: Side) -> np.ndarray:
    return torso + HANGING[side]


def gesturing(torso: np.ndarray, side: Side, t: float) -> np.ndarray:
    """Both hands up in front of the chest, circling 150 mm, never down at rest."""
    sign = -1.0 if side is Side.LEFT else 1.0
    return torso + np.array([sign * 250 + 150 * np.cos(3 * t), 150 + 150 * np.sin(3 * t), -350.0])


Script = list[tuple[float, Callable[[float], tuple[dict, np.ndarray]]]]


def torso_errors(script: Script) -> list[tuple[float, np.ndarray]]:
    """Feed hands only (no torso, no head) along `script` ((seconds, hands_at(t) -> ({side: place},
    true torso))); return (t, estimated torso minus the true torso, mm) of every posture."""
    stream, out, t0 = PostureStream(mirrored=True), [], 0.0
    for seconds, hands_at in script:
        for k in range(int(seconds * RATE)):
            t = t0 + k / RATE
            places, torso = hands_at(t)
            hands = [Hand(i, HandState.TRACKING, tuple(p), side) for i, (side, p) in enumerate(places.items(), 1)]
            for posture in stream.update(t, hands, {}):
                estimated = places[Side.LEFT] - (posture.vector[:3] * SIZE)  # posture = (hand - torso) / size
                out.append((t, estimated - torso))
        t0 += seconds
    return out


def test_a_performer_gesturing_on_and_on_keeps_their_torso_where_they_rested():
    torso = np.array([0.0, 0.0, 2500.0])
    rest = lambda t: ({s: at_rest(torso, s) for s in HANGING}, torso)
    up = lambda t: ({s: gesturing(torso, s, t) for s in HANGING}, torso)
    errors = torso_errors([(3.0, rest), (20.0, up)])
    late = np.array([e for t, e in errors if t > 8.0])  # hands up for 5 s and more: a few seconds' rest is long gone
    assert np.abs(late).max() < 30.0


def test_a_performer_who_walks_is_followed_from_rest_to_rest():
    here, there = np.array([0.0, 0.0, 2500.0]), np.array([1000.0, 0.0, 2000.0])
    script = [(3.0, lambda t: ({s: at_rest(here, s) for s in HANGING}, here)),
              (5.0, lambda t: ({s: gesturing(here, s, t) for s in HANGING}, here)),
              (3.0, lambda t: ({s: at_rest(here + (there - here) * (t - 8.0) / 3.0, s) for s in HANGING},
                               here + (there - here) * (t - 8.0) / 3.0)),  # walks over, hands hanging
              (3.0, lambda t: ({s: at_rest(there, s) for s in HANGING}, there)),
              (5.0, lambda t: ({s: gesturing(there, s, t) for s in HANGING}, there))]
    errors = torso_errors(script)
    after = np.array([e for t, e in errors if t > 15.0])  # gesturing again after the rest there
    assert np.abs(after).max() < 30.0


def test_a_tick_falls_on_the_sample_whose_timestamp_was_rounded_just_before_it():
    """30 Hz samples stamped to the millisecond (0.133 for 4/30 s): each 15 Hz posture comes with the
    sample it falls on, not one sample (33 ms) later."""
    stream, late = PostureStream(mirrored=True), []
    place = {side: tuple(at_rest(np.zeros(3), side)) for side in HANGING}
    for k in range(90):
        t = round(k / RATE, 3)
        hands = [Hand(i, HandState.TRACKING, place[side], side) for i, side in enumerate(place, 1)]
        late += [round(t - p.t, 4) for p in stream.update(t, hands, {"torso": (0.0, 0.0, 0.0), "head": (0.0, SIZE, 0.0)})
                 if t - p.t > 1e-3]
    assert late == []
