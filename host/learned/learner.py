"""Learning a gesture from takes: cut the repetitions, weigh the hands, derive the threshold.

The threshold comes from the taught repetitions themselves: each repetition is matched, as the
live recogniser would match it, against the other repetitions of its own take (a take of one
repetition: against all the others); its score says how consistently one person performs the
gesture. The acceptance threshold is THRESHOLD_FACTOR times the median of those scores: how far
a new performer may lie from the closest taught repetition, in units of the teachers' own
consistency. Scores against other people's takes were tried instead (their 90th percentile): two
or three teachers who perform a gesture differently then give a threshold that is far too loose
for some gestures and too tight for others (leave-one-teacher-out on MSRC-12 p01-p03, see
bench/learned.py). It is at most THRESHOLD_CEILING: repetitions far apart, as a tracker that loses
the hands makes them, would otherwise take almost anything for the gesture. A repetition whose
score is far above the others' is reported by its time so the artist can re-record it.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Sequence

import numpy as np

from host.errors import UserError
from host.learned.features import RATE_HZ, resampled
from host.learned.gesture_file import LearnedGesture, TaughtRepetition, hand_weights
from host.learned.matcher import Matcher
from host.learned.segment import find_repetitions

FIRES_AT = 0.75  # a learned gesture completes three quarters through: late enough to tell it from
# gestures that start alike (wind_it_up vs goggles), early enough to answer the motion; chosen with
# THRESHOLD_FACTOR leave-one-teacher-out on p01-p03 (0.5 gave recall - false fires 0.33, 0.75: 0.39)
THRESHOLD_FACTOR = 2.42  # chosen with matcher.AGREE leave-one-teacher-out on MSRC-12 p01-p03 (1.8 before the
# classifier veto, 2.34 before the classifier learned to say "none" to the unseen; see matcher.py)
THRESHOLD_FLOOR = 0.15  # body units: repetitions alike to the millimetre still leave room for sensor noise
BOTH_HANDS = 0.4  # the quieter hand counts as used if it moves this share of the busier one
OUTLIER = 2.0  # a repetition scoring this many times the median is reported as far off
MAX_REPETITIONS = 40  # more teach little that is new and cost time at every frame (10 gestures: bench.learned's
# `cost`, their templates at half pace included, matcher.SLOWER)
SHORTEST, LONGEST = 0.6, 1.8  # a repetition outside this share of the typical length is not learned
STYLE_MIN = 3  # repetitions: an example with this many, every one outside that share, is another pace of the gesture
THRESHOLD_CEILING = 1.3  # body units (about 0.7 m for an adult): a performance farther than this on average from
# every taught repetition is not the gesture, however far apart the repetitions are (`threshold`)


@dataclass
class Take:
    """One example: its name (file@window), posture times (s) and postures (n, 6)."""

    source: str
    t: np.ndarray
    postures: np.ndarray


def repetitions(take: Take) -> list[TaughtRepetition]:
    return [TaughtRepetition(take.source, r.t0, r.t1, take.postures[r.start:r.end])
            for r in find_repetitions(take.t, take.postures)]


def counter_example(take: Take) -> TaughtRepetition:
    """A take of what the gesture is not (`issv learn --unlike`), kept whole: every moment of it is
    "none" to the classifier (classifier.py), however much of it is rest."""
    return TaughtRepetition(take.source, float(take.t[0]), float(take.t[-1]), take.postures)


def typical_length(reps: Sequence[TaughtRepetition]) -> float:
    return float(np.median([r.duration for r in reps]))


def usual_length(duration: float, typical: float) -> bool:
    return SHORTEST <= duration / typical <= LONGEST


def own_paces(reps: list[TaughtRepetition], among: list[TaughtRepetition]) -> dict[str, float]:
    """The examples of `reps` performed at a pace of their own, with their typical length (s): at
    least STYLE_MIN repetitions, every one far shorter or longer than the typical one of `among`, made
    with the hands the others use. Not mistakes, which a performer does not repeat alike, but a style
    of the gesture (MSRC-12 p03 beats beat_both in front of the chest in half the others' time, as
    three of p04-p10 do). An example made with other hands is another gesture (p03's one-handed
    shoot, where p01 and p02 shoot with both). Chosen on p04-p07 (mean recall 0.852 -> 0.857, false
    fires 0.035 -> 0.032) and checked on p08-p10 (0.871 -> 0.904, 0.086 -> 0.087; beat_both on p04-p10
    0.76 -> 0.85); leaving one teacher out it costs p01 0.84 -> 0.75, whose wind_it_up the in-front
    beats of p03 alone draw away (bench/learned.py)."""
    typical = typical_length(among)
    paces = {}
    for source in dict.fromkeys(r.source for r in reps):
        mine = [r for r in reps if r.source == source]
        rest = [r for r in among if r.source != source]
        if (len(mine) >= STYLE_MIN and rest and not any(usual_length(r.duration, typical) for r in mine)
                and hands_used(mine)[0] == hands_used(rest)[0]):
            paces[source] = typical_length(mine)
    return paces


def odd_lengths(reps: list[TaughtRepetition], among: list[TaughtRepetition],
                paces: dict[str, float]) -> list[TaughtRepetition]:
    """Those of `reps` far shorter or longer than the typical one of `among`, or of their example's own
    pace (`own_paces`): two run together, or a twitch."""
    typical = typical_length(among)
    return [r for r in reps if not usual_length(r.duration, paces.get(r.source, typical))]


def hands_used(reps: list[TaughtRepetition]) -> tuple[str, np.ndarray]:
    """Which hands move ("left", "right", "both") and the posture weights that follow."""
    spread = []
    for hand in (slice(0, 3), slice(3, 6)):
        spread.append(float(np.median([np.linalg.norm(np.ptp(r.postures[:, hand], axis=0)) for r in reps])))
    left, right = spread
    if min(left, right) >= BOTH_HANDS * max(left, right):
        return "both", hand_weights("both")
    hands = "left" if left > right else "right"
    return hands, hand_weights(hands)


def consistency(gesture: LearnedGesture) -> np.ndarray:
    """Each repetition's best score against the other repetitions of its take (see the module doc)."""
    reps = gesture.repetitions
    out = np.full(len(reps), np.inf)
    for i, rep in enumerate(reps):
        others = [r for r in reps if r.source == rep.source and r is not rep] or [r for r in reps if r is not rep]
        if not others:
            continue
        alone = LearnedGesture(gesture.name, gesture.hands, 1.0, gesture.fires_at, gesture.weights, others)
        matcher = Matcher([alone], classify=False, one_arm=False)
        out[i] = min(float(matcher.step(posture)[0]) for posture in rep.postures)
    return out


def consistent_threshold(scores: Sequence[float | None]) -> float:
    """The threshold the repetitions' consistency scores give (see the module doc)."""
    finite = [s for s in scores if s is not None and np.isfinite(s)]
    return max(THRESHOLD_FLOOR, THRESHOLD_FACTOR * (float(np.median(finite)) if finite else 1.0))


def threshold(gesture: LearnedGesture) -> float:
    """The consistent threshold, at most THRESHOLD_CEILING. Repetitions far apart (a tracker that loses
    the hands) give a threshold so loose that only the classifier's weakest tier (matcher.CLOSE) tells
    the gesture from almost anything: UTD-MHAD's bowling taught from subjects 1 and 2's clips through
    the open engine, which loses the hands beside the legs, got 1.76 body units (0.64 from the
    skeleton's hands) and fired on 189 of subjects 3 and 4's 216 clips (bench/learned_depth.py); held
    at 1.3, on 14, its recall 1.00 -> 0.88. The ceiling was chosen leave-one-teacher-out on MSRC-12:
    1.3 holds none of the six (the loosest, change_weapon taught by p02 and p03, gives 1.26), 1.2 holds
    that one and costs p01's change_weapon 0.71 -> 0.66; p04-p10 are unchanged either way (the six
    taught by p01-p03 give 0.58-0.80, 0.66-0.91 with hands only)."""
    return min(consistent_threshold([r.score for r in gesture.repetitions]), THRESHOLD_CEILING)


def held_by_ceiling(gesture: LearnedGesture) -> float | None:
    """The threshold the repetitions' consistency gives when the ceiling held it lower, else None."""
    loose = consistent_threshold([r.score for r in gesture.repetitions])
    return loose if loose > THRESHOLD_CEILING + 1e-3 and abs(gesture.threshold - THRESHOLD_CEILING) < 1e-3 else None


def taught_before(gesture: LearnedGesture) -> list[TaughtRepetition]:
    """A learned gesture's repetitions, at RATE_HZ, to be learned again with new takes."""
    return [replace(r, postures=resampled(r.postures, gesture.rate_hz), score=None) for r in gesture.repetitions]


def unlike_before(gesture: LearnedGesture) -> list[TaughtRepetition]:
    """A learned gesture's counter-examples, at RATE_HZ, kept when it is taught more."""
    return [replace(u, postures=resampled(u.postures, gesture.rate_hz)) for u in gesture.unlike]


def learn(name: str, takes: list[Take], fires_at: float = FIRES_AT,
          before: Sequence[TaughtRepetition] = (), unlike: Sequence[TaughtRepetition] = ()) -> LearnedGesture:
    """The learned gesture; UserError when the takes hold fewer than two repetitions. `before`:
    repetitions of a gesture learned before (`taught_before`), learned again with the takes' own
    (a performer whose style the first teachers never showed, added to what they taught); `unlike`:
    counter-examples (`counter_example`), motions it must not be taken for."""
    found_now = [r for take in takes for r in repetitions(take)]
    found = {take.source: sum(r.source == take.source for r in found_now) for take in takes}
    reps = list(before) + found_now
    if len(reps) < 2:
        found = "one repetition" if reps else "no repetition"
        raise UserError(f"learn {name}: found {found} in {', '.join(t.source for t in takes)}; perform the "
                        "gesture at least twice, from rest back to rest, with a moment of stillness between")
    # lengths are judged within this teaching (a file's repetitions were judged when it was taught):
    # a performer slower than the file's teachers is learned, not left out as odd
    paces, odd = {}, []
    if len(reps) >= 3:
        among = found_now if len(found_now) >= 3 else reps
        paces = own_paces(found_now, among)
        odd = odd_lengths(found_now, among, paces)
    reps = [r for r in reps if r not in odd]
    if len(reps) > MAX_REPETITIONS:
        reps = [reps[i] for i in np.linspace(0, len(reps) - 1, MAX_REPETITIONS).round().astype(int)]
    hands, weights = hands_used(reps)
    gesture = LearnedGesture(name, hands, 1.0, fires_at, weights, reps, RATE_HZ)
    gesture.left_out, gesture.found, gesture.paces, gesture.unlike = odd, found, paces, list(unlike)
    for rep, score in zip(reps, consistency(gesture)):
        rep.score = float(score) if np.isfinite(score) else None
    gesture.threshold = threshold(gesture)
    return gesture


def examples_left_out(gesture: LearnedGesture) -> list[str]:
    """The examples (of two repetitions or more) of which none was learned, every one far shorter or
    longer than the typical one: not repetitions run together, but made with other hands than the
    others (another gesture), or too few to be a pace of their own (`own_paces`)."""
    return [source for source, count in gesture.found.items()
            if count >= 2 and sum(r.source == source for r in gesture.left_out) == count]


def far_off(gesture: LearnedGesture) -> list[TaughtRepetition]:
    """The repetitions unlike the others: scoring above OUTLIER times the median score, and above
    THRESHOLD_FLOOR (closer than sensor noise is not far, however alike the others are: a looped
    recording taught live repeats itself to the sample)."""
    scores = [r.score for r in gesture.repetitions if r.score is not None]
    if len(scores) < 3:
        return []
    limit = max(OUTLIER * float(np.median(scores)), THRESHOLD_FLOOR)
    return [r for r in gesture.repetitions if r.score is not None and r.score > limit]
