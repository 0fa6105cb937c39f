"""Online matching of learned gestures: dynamic time warping of the live postures against every
taught repetition at once.

Each repetition is a template, and so is the repetition performed SLOWER times slower; the live
stream may match them starting at any instant (subsequence DTW). Every posture the stream advances,
a template advances by 0, 1 or 2 of its own postures, so a performance may be up to twice as fast as
the teaching, and up to four times as slow (the band: a path may not hold more than its own length in
stays, on the slow template too). A path's score is the mean weighted
distance between the live postures and the template's along it. A gesture completes when, for
HOLD postures running, its best template has been matched up to its `fires_at` point with a
score below the gesture's threshold AND the classifier (classifier.py) agrees, the more so the
further the template is: below CLOSE_RATIO of the threshold a probability above CLOSE (the
classifier does not rule it out: a style the teachers never showed, slower or wider circles, that
the classifier is unsure of), below the threshold above AGREE, and up to SURE_RATIO times the
threshold above SURE (the classifier all but certain: circles made elsewhere than the
teachers'). The templates say "close to a taught repetition", the classifier "more like this
gesture than like the others loaded, or like rest". Templates alone cannot tell wind_it_up from
goggles or shoot (the hands go up to the front in all three); a classifier alone fires on
gestures it never saw (nothing tells it about a bow). Together, on MSRC-12 taught by p01-p03 and
scored leave-one-teacher-out: recall 0.66 with false fires 0.075 (templates alone, at their best
threshold: 0.48 with 0.09; with AGREE 0.85 and no CLOSE tier: 0.63 with 0.075, and on p04-p10 0.84
with 0.087 against 0.86 with 0.093). A gesture its teachers perform as a loop must also loop
(loops.py, read on the motion its best template has matched, at one of the HOLD postures): on
p04-p10 the false fires fall to 0.057 with the same recall, leave-one-teacher-out nothing changes.
The threshold factor (learner.py), AGREE, CLOSE, SURE (and their ratios), HOLD, FRESH and the
classifier's shifts were chosen there, as the highest recall with false fires no higher than before
(people other than the teachers gave about 1.2 to 1.3 times the teachers' false fires before the
loop check); bench/learned.py gives the figures, on the teachers and on p04-p10. The postures of all
templates of all gestures sit one after another in one array (not padded to the longest template:
that was two thirds padding), so a frame costs a handful of numpy operations whatever their number.

A performer may wind a loop far slower than its teachers: MSRC-12's p06 winds one circle of
wind_it_up in 2.5 s, the teachers one in 0.7 s. The slow templates match such a performance, and a
looping gesture (loops.py) whose best template is a slow one is asked of the classifier at that
pace, every SLOWER-th posture (`_agree`): its window, 1.6 s at the taught pace, would hold only part
of the loop. A one-off gesture's shape comes with its pace (a shoot's recoil, a throw's release):
read at half pace too, p04-p10's shoot windows fired beat_both three times as often (30 against
10) and, leaving one teacher out, false fires rose 0.083 -> 0.107 (at AGREE 0.88). With the slow
templates AGREE was chosen again as before (the highest recall leaving one teacher out with false
fires no higher than before): 0.88 -> 0.935. Leaving one teacher out, mean recall 0.644 -> 0.691 with
false fires 0.073 -> 0.070; on p04-p10 0.879 -> 0.890 (wind_it_up 0.61 -> 0.70: p04 0.50 -> 0.86,
p06 0 -> 0.18, p09 0 -> 0.25; beat_both 0.85 -> 0.87) with false fires 0.056 -> 0.082, most of
them wind_it_up in p08's beat_both and p09's shoot. The slow templates make matching about three
times as costly (twice the templates, twice as long): bench/learned.py prints it. Once the loop check
asked for a loop gone round in all a template has matched (loops.py), AGREE was chosen again by the
same rule: 0.935 -> 0.92 (0.91 gave false fires 0.073 leaving one teacher out). Leaving one teacher
out, 0.691 / 0.070 -> 0.694 / 0.070; on p04-p10 0.890 / 0.082 -> 0.895 / 0.078.

The loop need not pass at all HOLD postures, only at one of them: where the loop closes moves as the
match goes on, so a loop found at one posture may not be found at the next (`_decide`). MSRC-12 p04
rolls high and wide; templates and classifier agreed for three postures running and more, the loop
passed at one or two of them, and wind_it_up was missed (2 of p04's 14). Asked at one of them, AGREE
was chosen again by the same rule: 0.92 -> 0.925 (0.92 gave false fires 0.073 leaving one teacher
out). Leaving one teacher out, 0.694 / 0.070 -> 0.697 / 0.070; on p04-p10 0.895 / 0.078 -> 0.897 /
0.082 (wind_it_up 0.71 -> 0.73: p04 0.79 -> 0.93, p06 0.27 -> 0.45); with hands only 0.889 / 0.107
-> 0.894 / 0.123.

Near a template, the classifier need only not rule a looping gesture out among the looping
gestures and "none", at each posture its loop is found (`_agree`, `_decide`): the loop tells a
roll from gestures that do not loop, which the classifier cannot see. MSRC-12 p06 winds slow, wide
circles; with a wind_it_up template within CLOSE_RATIO of the threshold and the loop found, the
classifier took them for beat_both (0.95-0.97, wind_it_up under CLOSE) and they were missed. On
p04-p10 wind_it_up 0.733 -> 0.747 (p06 0.45 -> 0.64), false fires 0.0818 -> 0.0825 (one window);
leaving one teacher out nothing changes. Asked at every tier, not near a template only, false fires
rose to 0.111 on p04-p10 (wind_it_up in 109 windows of other gestures instead of 57) and to 0.094
leaving one teacher out, with the same recall there.

A looping gesture taught with both hands is also matched on each arm alone (`forms`): its
repetitions with the other hand held where it began, weighted as an unused hand, as templates of
their own; completing any form completes the gesture, once (a completion cuts every form's paths).
MSRC-12's teachers wind it up with both hands; p09 swings one arm at a time in a big circle, and
the two-handed templates stayed 1.3-1.7 times the threshold away. A form on one arm must go round a
loop as big as a taught hand's (loops.py): one hand moving alone draws smaller loops all the time
(MSRC-12's push_right and kick fired wind_it_up in 23 more windows of p04-p10 without it). The
classifier is trained on the gestures as taught, not on these forms: trained on them too,
wind_it_up was found in 0.96 of p04-p10's instances but fired in windows of other gestures at 0.11
(0.175 without the loop's size and facing), above the target. On p04-p10 (taught by p01-p03), with
the loop's facing (loops.py): wind_it_up 0.747 -> 0.815 (p09 5 -> 14 of 20, p07 38 -> 39 of 55: its
right arm rolled alone is read as rest by the classifier), mean 0.899 -> 0.911, false fires 0.0825
-> 0.0859; leaving one teacher out, 0.697 / 0.070 -> 0.694 / 0.076 (wind_it_up 0.633 -> 0.612; the
facing's 45-degree floor, loops.py, adds the false fires).

A gesture is IN_PROGRESS (said once per attempt) when a path has come UNDER_WAY of the way to its
`fires_at` point with a score below the threshold and the classifier does not rule it out (above
CLOSE, the least any completion asks); the attempt is over when it completes or when no path past
that point is below the threshold any more. Templates alone announced what could not complete:
taught by MSRC-12 p01-p03, 40 attempts a minute while Kinder-Gator's people walked, ran or jumped,
and on p04-p10 one announced attempt in six completed; with the classifier 10 a minute and one in
three, the COMPLETEs unchanged, announced 0.53 s before them (median) instead of 0.80 s.

Gestures are matched independently. When one completes, only paths that begin after that (or at
most FRESH of its typical length before) may complete it again: the rest of the same motion, or a
pose held, cannot fire it twice, but the next repetition can, however soon it follows (a cyclic
gesture such as wind_it_up fires once per cycle; a long beat_both performance once per beat
phrase). A fixed rest of 0.8 of the typical length used to swallow repetitions that followed
quickly: MSRC-12 beat_both performances that complete 1.5-2 s before the action point were not
completed again within its window (recall 0.55 -> 0.73 on p04-p10).
"""
from __future__ import annotations

import copy
from collections import deque
from dataclasses import dataclass
from itertools import islice

import numpy as np

from host.learned.cache import trained
from host.learned.classifier import Classifier, Describer
from host.learned.features import RATE_HZ, resampled
from host.learned.gesture_file import LearnedGesture
from host.learned.loops import LoopCheck

MOTION_WEIGHT = 0.5  # how much the direction of motion counts next to where the hands are
MOTION_SOFT = 1.0  # body units/s: motion slower than this counts less (direction of a still hand is noise)
SKIP_WEIGHT = 2.0  # a skip covers two template postures: it counts twice
FRESH = 0.2  # a completion needs a path begun after the last one, or at most this share of the typical length before
AGREE = 0.925  # the classifier's probability a gesture needs to complete with a template below the threshold
# (chosen leave-one-teacher-out on p01-p03 with the other tiers and learner.THRESHOLD_FACTOR; see the module doc)
SURE, SURE_RATIO = 0.999, 1.5  # ... or this probability with a template up to SURE_RATIO times the threshold away
CLOSE, CLOSE_RATIO = 0.02, 0.62  # ... or only this one with a template within CLOSE_RATIO of the threshold
HOLD = 3  # postures running that both must agree (a one-posture blip is no gesture)
UNDER_WAY = 0.5  # share of the way to `fires_at` a path must have come, below threshold, to be IN_PROGRESS
SLOWER = 2  # every repetition is also a template performed this many times slower (see the module doc)


@dataclass(frozen=True)
class Match:
    """A learned gesture recognised: which, how well (score / threshold < 1), its state, and in
    which of its forms (`Matcher.forms`: as taught, or on one arm alone)."""

    index: int
    ratio: float
    complete: bool
    form: int


def motion(postures: np.ndarray) -> np.ndarray:
    """Each posture with where it is heading: per hand, its velocity over the last two ticks,
    softly normalised (v / (|v| + MOTION_SOFT)) so a faster performer heads the same way."""
    back = np.concatenate([postures[:1], postures[:1], postures[:-2]])[:len(postures)]
    if len(postures) > 1:
        back[1] = postures[0]
    v = (postures - back) * (RATE_HZ / 2)
    out = []
    for hand in (slice(0, 3), slice(3, 6)):
        speed = np.linalg.norm(v[:, hand], axis=1, keepdims=True)
        out.append(MOTION_WEIGHT * v[:, hand] / (speed + MOTION_SOFT))
    return np.concatenate([postures] + out, axis=1)


def taught_repetitions(gestures: list[LearnedGesture]) -> list[list[np.ndarray]]:
    """Each gesture's repetitions at RATE_HZ: the templates, and what the classifier is trained on."""
    return [[resampled(r.postures, g.rate_hz) for r in g.repetitions] for g in gestures]


def counter_examples(gestures: list[LearnedGesture]) -> list[list[np.ndarray]]:
    """Each gesture's counter-examples at RATE_HZ: "none" to the classifier."""
    return [[resampled(u.postures, g.rate_hz) for u in g.unlike] for g in gestures]


def forms(gestures: list[LearnedGesture], looping: np.ndarray) -> tuple[list[LearnedGesture], np.ndarray]:
    """What is matched: each gesture as taught and each of the `looping` ones ((gestures,) bool)
    taught with both hands performed with either arm alone (`with_one_arm`); and the gesture each
    form is of. Such a form completes only on a loop as big as a taught hand's (loops.py)."""
    out, of = list(gestures), list(range(len(gestures)))
    for gi in np.flatnonzero(looping):
        if gestures[gi].hands == "both":
            out += [gestures[gi].with_one_arm(side) for side in ("left", "right")]
            of += [gi, gi]
    return out, np.array(of, int)


class Matcher:
    """Fed one posture at a time (RATE_HZ); says which learned gestures it completes."""

    def __init__(self, gestures: list[LearnedGesture], thresholds: list[float] | None = None,
                 classify: bool = True, classifier: Classifier | None = None, one_arm: bool = True) -> None:
        """`classify=False`: templates alone (the learner's consistency check, which needs no veto);
        `classifier`: one already trained on these gestures (else the one of this set, cache.py);
        `one_arm=False`: no looping gesture taught with both hands is matched on one arm (`forms`)."""
        self.gestures = gestures
        taught = taught_repetitions(gestures)
        loops = LoopCheck(gestures, taught)
        self.forms, self.gesture_of_form = forms(gestures, loops.checked & one_arm)
        one_armed = self.forms[len(gestures):]
        forms_taught = taught + taught_repetitions(one_armed)
        self.loops = loops.joined(LoopCheck(one_armed, forms_taught[len(gestures):], one_arm=True))
        thresholds = np.array(thresholds if thresholds is not None else [g.threshold for g in gestures], float)
        self.thresholds = thresholds[self.gesture_of_form]
        # a threshold loosened in a profile does not loosen "close": look-alikes still need the classifier
        self.close = CLOSE_RATIO * np.minimum(thresholds, [g.threshold for g in gestures])[self.gesture_of_form]
        prefixes, owner, pace, typical = [], [], [], []
        for fi, (form, reps) in enumerate(zip(self.forms, forms_taught)):
            typical.append(float(np.median([len(r) for r in reps])))
            for r in reps:
                for slower in (1, SLOWER):
                    postures = resampled(r, RATE_HZ / slower)
                    prefixes.append(motion(postures)[:form.completes_at(len(postures))])
                    owner.append(fi)
                    pace.append(slower)
        owner = np.array(owner, int)
        self.slow = np.array(pace) > 1  # a template of a repetition performed SLOWER times slower
        self._templates_of = [np.flatnonzero(owner == fi) for fi in range(len(self.forms))]
        # every template's postures one after another, form by form: padded to the longest, the
        # templates would be mostly padding (the slow ones are twice as long)
        lengths = np.array([len(p) for p in prefixes], int)
        self.end = np.cumsum(lengths) - 1  # each template's last posture
        place = np.concatenate([np.arange(n) for n in lengths]) if len(lengths) else np.zeros(0, int)
        self._first = np.flatnonzero(place == 0)  # postures with none before them in their template
        self._second = np.flatnonzero(place <= 1)  # ... with fewer than two
        of = np.repeat(np.arange(len(lengths)), lengths)  # each posture's template
        self._form_templates = np.array([rows[0] for rows in self._templates_of], int)  # each form's first
        self._form_postures = (self.end - lengths + 1)[self._form_templates]  # ... and its first posture
        bounds = [*self._form_postures, len(place)]
        self._postures_of = [slice(a, b) for a, b in zip(bounds, bounds[1:])]  # each form's postures
        under_way = np.maximum(1, np.round(UNDER_WAY * (lengths - 1))).astype(int)
        self.late = place >= under_way[of]  # past the point an attempt counts as under way
        self.templates = np.concatenate(prefixes, dtype=np.float32) if prefixes else np.zeros((0, 12), np.float32)
        self.weights = np.array([np.tile(f.weights, 2) for f in self.forms], np.float32).reshape(-1, 12)[owner[of]]
        self.band = 2.0 * (place + 1)  # at most twice as slow as the template
        self.overlap = np.array([FRESH * t for t in typical])  # ticks, per form
        self.classifier = classifier or (trained(taught, counter_examples(gestures)) if classify and gestures else None)
        self._span = 2 * int(lengths.max(initial=1)) + 1  # postures a path may span
        self._begin()

    def _begin(self) -> None:
        """No posture seen yet: what one stream (one performer) has matched so far."""
        self.cost = np.full(len(self.templates), np.inf, np.float32)  # distance summed along the best path ending here
        self.steps = np.ones(len(self.templates), np.float32)  # its weight (template postures covered, stays included)
        self.start = np.zeros(len(self.templates), np.int64)  # the tick at which that path began
        self._recent: list[np.ndarray] = []  # the last two postures: where the hands are heading
        self.tick = 0  # postures seen
        self._cutoff = np.full(len(self.templates), -1e9)  # per posture: a fresh path began after this tick
        self.announced = np.zeros(len(self.gestures), bool)  # IN_PROGRESS said for the current attempt
        self._history: deque[np.ndarray] = deque(maxlen=self._span)
        self._score = np.full(len(self.end), np.inf)  # each template's score at its `fires_at` point, this posture
        self.describer = Describer()
        self.slow_describer = Describer(pace=SLOWER)
        self.running = np.zeros(len(self.forms))  # postures templates and classifier have agreed
        self.looped = np.zeros(len(self.forms), bool)  # ... and the loop check passed at one of them

    def fresh(self) -> "Matcher":
        """A matcher of the same gestures for another stream (another performer), with nothing seen:
        the templates, classifier and loop check are shared, not built again (that takes a few
        hundred milliseconds, a stall in the show when a performer walks in)."""
        other = copy.copy(self)
        other._begin()
        return other

    def reset(self) -> None:
        """The stream broke (a hand gone): no path continues across the gap."""
        self.cost[:] = np.inf
        self.announced[:] = False
        self._recent = []
        self._history.clear()
        self.describer.reset()
        self.slow_describer.reset()
        self.running[:] = 0
        self.looped[:] = False

    def update(self, posture: np.ndarray) -> list[Match]:
        """One posture (6,) in; the gestures it puts under way (IN_PROGRESS) and the one it completes."""
        if not len(self.gestures):
            return []
        self._history.append(posture)
        per = self.step(posture)
        agree, among_loops = self._agree(posture)
        # the loop is read only where it could make a difference: forms that agree if it is found
        possible = self._agreed(per, np.ones(len(self.forms), bool), agree, among_loops)
        looped = self.loops.passes(self._matched, possible)
        return self._announce(agree) + self._decide(per, looped, agree, among_loops)

    def _agree(self, posture: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Per form, the classifier's probability of its gesture: at the taught pace, and for a
        looping form whose best template is a slow one, at that pace (every SLOWER-th posture). And of
        a looping form's gesture among the looping gestures and "none" only (0 for the others): where
        its loop is found, the gestures that do not loop are told apart by that (`_decide`)."""
        if self.classifier is None:
            return np.ones(len(self.forms)), np.zeros(len(self.forms))
        probabilities = self.classifier.probabilities(self.describer.push(posture))
        read = np.tile(probabilities, (len(self.forms), 1))  # row f: what form f is read by
        checked = self.loops.checked
        if checked.any():
            self.slow_describer.add(posture)
            slow = [fi for fi in np.flatnonzero(checked) if self.slow[self._best(fi)]]
            if slow:
                read[slow] = self.classifier.probabilities(self.slow_describer.descriptor())
        agree = read[np.arange(len(self.forms)), self.gesture_of_form]
        rivals = read[:, -1] + read[:, :-1][:, checked[:len(self.gestures)]].sum(axis=1)
        among_loops = np.where(checked, agree / np.maximum(rivals, 1e-12), 0.0)
        return agree, among_loops

    def _best(self, fi: int) -> int:
        """The template of form `fi` that matches best at its `fires_at` point, this posture."""
        rows = self._templates_of[fi]
        return int(rows[np.argmin(self._score[rows])])

    def step(self, posture: np.ndarray) -> np.ndarray:
        """Advance every path by one posture; each form's best score at its `fires_at` point, of the
        paths that began after its gesture's last completion (see `_fresh`)."""
        self._recent = (self._recent + [posture])[-3:]
        posture = motion(np.array(self._recent))[-1]
        diff = self.templates - posture.astype(np.float32)
        d = np.sqrt(np.einsum("nc,nc->n", diff * self.weights, diff))
        cost, steps, start = self.cost, self.steps, self.start
        best = np.empty_like(cost)  # one step along the template (a fresh start at its first posture)
        best[1:] = cost[:-1] + d[1:]
        best[self._first] = d[self._first]
        new_steps = np.empty_like(steps)
        new_steps[1:] = steps[:-1] + 1.0
        new_steps[self._first] = 1.0
        new_start = np.empty_like(start)
        new_start[1:] = start[:-1]
        new_start[self._first] = self.tick
        skip = np.full_like(cost, np.inf)  # two steps along it
        skip[2:] = cost[:-2] + SKIP_WEIGHT * d[2:]
        skip[self._second] = np.inf
        better = skip < best
        best = np.where(better, skip, best)
        new_steps[2:] = np.where(better[2:], steps[:-2] + SKIP_WEIGHT, new_steps[2:])
        new_start[2:] = np.where(better[2:], start[:-2], new_start[2:])
        stayed = steps + 1.0
        stay = np.where(stayed <= self.band, cost + d, np.inf)  # the template waits
        better = stay < best
        self.cost = np.where(better, stay, best)
        self.steps = np.where(better, stayed, new_steps)
        self.start = np.where(better, start, new_start)
        self.tick += 1
        end = self.end
        self._score = np.where(self._fresh(self.start[end], end), self.cost[end] / self.steps[end], np.inf)
        return np.minimum.reduceat(self._score, self._form_templates)

    def _matched(self, fi: int) -> np.ndarray:
        """The motion the loop check reads (loops.py): all that form `fi`'s best path has matched."""
        best = self._best(fi)
        seen = int(self.tick - self.start[self.end[best]])
        if not 0 < seen <= len(self._history):
            return np.zeros((0, 6))
        return np.array(list(islice(self._history, len(self._history) - seen, None)))

    def _fresh(self, start: np.ndarray, at: np.ndarray | slice = slice(None)) -> np.ndarray:
        """Paths (started at ticks `start`, ending at template postures `at`) that may complete their
        gesture: begun after its last completion, or at most FRESH of its typical length before. So the
        motion of one performance completes it once however long it lasts, and the next repetition
        right after it (a cyclic gesture, beaten again and again) completes it again."""
        return start > self._cutoff[at]

    def _announce(self, agree: np.ndarray) -> list[Match]:
        """IN_PROGRESS for each gesture with a path under way below its threshold (in one of its
        forms) that the classifier (`agree`) does not rule out, once per attempt."""
        score = np.where(self.late & self._fresh(self.start), self.cost / self.steps, np.inf)
        ratio = np.minimum.reduceat(score, self._form_postures) / self.thresholds
        ready = (ratio < 1.0) & (agree > CLOSE)
        self.announced &= self._per_gesture(ratio < 1.0)  # no path below threshold any more: that attempt is over
        out = []
        for gi in np.flatnonzero(self._per_gesture(ready) & ~self.announced):
            candidates = np.flatnonzero(ready & (self.gesture_of_form == gi))
            fi = int(candidates[np.argmin(ratio[candidates])])
            out.append(Match(int(gi), float(ratio[fi]), False, fi))
            self.announced[gi] = True
        return out

    def _per_gesture(self, per_form: np.ndarray) -> np.ndarray:
        """(gestures,) bool: true for one of the gesture's forms."""
        out = np.zeros(len(self.gestures), bool)
        np.logical_or.at(out, self.gesture_of_form, per_form)
        return out

    def _agreed(self, per: np.ndarray, looped: np.ndarray, agree: np.ndarray, among_loops: np.ndarray) -> np.ndarray:
        """Per form, whether its templates (`per`) and the classifier (`agree`) agree at this posture:
        the further the template, the surer the classifier must be (see the module doc)."""
        ratio = per / self.thresholds
        not_ruled_out = (agree > CLOSE) | (looped & (among_loops > CLOSE))
        return ((per < self.close) & not_ruled_out) | ((ratio < 1.0) & (agree > AGREE)) | \
            ((ratio < SURE_RATIO) & (agree > SURE))

    def _decide(self, per: np.ndarray, looped: np.ndarray, agree: np.ndarray,
                among_loops: np.ndarray) -> list[Match]:
        """COMPLETE for each gesture one of whose forms' templates (`per`) and classifier (`agree`)
        have agreed for HOLD postures running, its loop (`looped`, loops.py) found at one of them at
        least. A looping form whose template is close and whose loop is found at this posture needs
        only not to be ruled out among the looping gestures and "none" (`among_loops`, see `_agree`)."""
        ratio = per / self.thresholds
        agreed = self._agreed(per, looped, agree, among_loops)
        self.running = np.where(agreed, self.running + 1, 0)
        self.looped = np.where(agreed, self.looped | looped, False)
        out = []
        for fi in np.flatnonzero((self.running >= HOLD) & self.looped):
            gi = int(self.gesture_of_form[fi])
            if not self.running[fi]:  # another form of the same gesture completed it this posture
                continue
            for sibling in np.flatnonzero(self.gesture_of_form == gi):  # the same motion completes it once
                self._cutoff[self._postures_of[sibling]] = self.tick - self.overlap[sibling]
                self.running[sibling] = 0
                self.looped[sibling] = False
            if not self.announced[gi]:  # not said yet (the classifier alone was sure): say so, then complete
                out.append(Match(gi, float(ratio[fi]), False, int(fi)))
            self.announced[gi] = False
            out.append(Match(gi, float(ratio[fi]), True, int(fi)))
        return out
