"""The gesture recogniser of the open engine: hand positions in, gesture events out.

It runs on any stream of hand positions in millimetres (the depth tracker, a skeleton, a
recorded trajectory), once per frame. Motion is judged relative to the body (the torso and head
when given, else estimated from the hands, see body_reference.py), cut into strokes (strokes.py) and
matched against the rules (rules.py):

- SWIPE_LEFT/RIGHT/UP/DOWN: one fast stroke, dominant along its axis, with the hand up from
  rest (a sideways one may sweep out at waist height, see `raised`) and the body steady (not
  rising or sinking; with a skeleton, not rocking towards or away from the camera from shortly
  before the stroke until the swipe completes, as a kick or a lunge does, see steadiness.py). It
  completes `swipe_confirm_s` after it ends (or once a sideways stroke the hand turned straight
  into ends) unless a comparable stroke the other way follows: then the stronger of the two
  (further and faster) is the swipe and the other its wind-up or return, or both are part of a
  back-and-forth (neither is a swipe); the third of quick alternating strokes at a wave's height
  is a wave's, never a swipe, but sweeps slower than a wave's swings, or lower than a wave, are
  swipes each. A sideways swipe may also rise straight from the hanging arm across the body, out
  in front (`swept_up_across`). A reversal of a frame or two is a tracker's glitch: the strokes
  either side of it are one. If the hand leaves the view meanwhile, the swipe completes, except a
  swipe down: a hand lost after a stroke down went back to rest (a swipe down waits while its hand
  is unseen), as did one that goes on down to rest after a glitch cut its stroke short.
- WAVE: several direction reversals of horizontal swings, from the wrist (4 cm) to the whole arm,
  each quick, reaching the shoulders' height or above (the first may be the arm swinging up
  into the wave from lower), with the other hand elsewhere (hands at the eyes or on the head, or
  clapping, are no wave). Swings too small for strokes (a hand waved with the fingers) are a wave
  by their rhythm: six in a row, quick, mostly sideways, the hand at the shoulders or higher
  (rhythm.py).
- CLICK (PUSH): a fast stroke towards the camera ending far in front of the body at chest height,
  still heading forward at its end (from the chest, or rising from a hanging hand), after which
  the hand halts (stops or comes back); not an arm's swing (running, walking, squatting).
- HAND_RAISE: the hand up above the head and clear of it (hands put on the head are no raise),
  then stopping: at the top of a lift, or held there; or kept up there, however it moves, for
  `raise_hold_s` (arms lifted overhead may flap and never stop).
Distance thresholds are stated for an adult and scale with the performer's size (the torso to
head distance), so a child's smaller swipe across is still a swipe (swipes up and down keep an
adult's travel).
Swipes and waves are one hand's: another hand making the mirror motion at the same time (a
clap) cancels them. An arm has one hand: a new hand on the side of one lost from view just now is
that hand found again (a depth tracker outrun by a flick), going on from its strokes after a gap.

Each gesture is reported IN_PROGRESS (at most once per attempt) when it is recognisably under
way (a swipe: once its stroke has ended and waits for confirmation; a wave: one reversal before
it completes; a click: while the hand moves forward fast enough; a raise: half way through the
hold) and COMPLETE once; after a COMPLETE the hand has a refractory period (its return is no
gesture), which a raise ends after a swipe up: the hand held up where the swipe took it.
"""
from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import numpy as np

from backends.engine.body_reference import BodyReference
from backends.engine.rhythm import Rhythm
from backends.engine.rules import GestureRules
from backends.engine.steadiness import lurch
from backends.engine.strokes import X, Y, Z, AxisStrokes, Sample, Stroke
from host import CANONICAL_GESTURES, Gesture, GestureState, GestureType, Hand, Side, Vec3

#: The dictionaries of the engine's modes: canonical name -> the native type it is reported as.
OPENISS_DICTIONARY: dict[str, GestureType] = {n: GestureType.from_canonical(n) for n in CANONICAL_GESTURES}
NITE_DICTIONARY: dict[str, GestureType] = {
    "wave": GestureType.WAVE, "click": GestureType.CLICK, "hand_raise": GestureType.HAND_RAISE}
NUITRACK_DICTIONARY: dict[str, GestureType] = {
    "wave": GestureType.WAVING, "click": GestureType.PUSH,
    "swipe_left": GestureType.SWIPE_LEFT, "swipe_right": GestureType.SWIPE_RIGHT,
    "swipe_up": GestureType.SWIPE_UP, "swipe_down": GestureType.SWIPE_DOWN}

_HISTORY_S = 3.0  # how much of each hand's past is kept (longer than any gesture)


def _drop(stroke: Stroke) -> bool:
    """A stroke down: a swipe down, or an arm going back to rest if the hand is lost after it."""
    return stroke.axis == Y and stroke.direction < 0


def _around(jitter: Stroke | None, before: Stroke | None, after: Stroke | None) -> bool:
    """Is `jitter` a reversal held back between `before` and `after`, which go the same way (so that the
    three may be one stroke, `_HandTrack.joined`)?"""
    return (jitter is not None and before is not None and after is not None and before.direction == after.direction
            and before.end is jitter.start and jitter.end is after.start)


def _continues(chain: list[Stroke], stroke: Stroke, max_gap_s: float) -> bool:
    """Does `stroke` go back the other way from the last of `chain`, starting within `max_gap_s` of its end?"""
    return bool(chain) and chain[-1].direction == -stroke.direction and stroke.start.t - chain[-1].end.t <= max_gap_s


def _extend(chain: list[Stroke], stroke: Stroke, counts: bool, max_gap_s: float) -> None:
    """Alternating strokes, each starting within `max_gap_s` of the last: add `stroke` if it
    `counts`, else the run is broken."""
    if chain and not _continues(chain, stroke, max_gap_s):
        chain.clear()
    if counts:
        chain.append(stroke)
    else:
        chain.clear()


def _merged(before: Stroke, jitter: Stroke, after: Stroke) -> Stroke:
    """One stroke of `before` and `after`, the same way, and the tracker's `jitter` between them."""
    return Stroke(before.axis, before.direction, before.samples + jitter.samples[1:] + after.samples[1:])


def _during(track: _HandTrack, stroke: Stroke) -> list[Sample]:
    """Another hand's samples while `stroke` was under way."""
    return [q for q in track.samples if stroke.start.t <= q.t <= stroke.end.t]


def _margin(value: float, threshold: float) -> float:
    """0 at the threshold, 1 at twice the threshold (or more)."""
    return float(np.clip(value / threshold - 1.0, 0.0, 1.0)) if threshold > 0 else 1.0


def _confidence(*margins: float) -> float:
    """A gesture that just passes its thresholds gets 0.5; one that passes them twice over, 1."""
    return 0.5 + 0.5 * float(np.mean(margins))


@dataclass
class _HandTrack:
    """Everything the recogniser remembers about one hand."""

    rules: GestureRules
    hand: Hand  # as last seen
    last_seen: float = 0.0
    samples: deque = field(default_factory=deque)
    refractory_until: float = float("-inf")
    last_complete: str | None = None  # the hand's last COMPLETE gesture
    pending: dict[int, Stroke] = field(default_factory=dict)  # per axis: a swipe waiting for confirmation
    chains: dict[int, list[Stroke]] = field(default_factory=lambda: {X: [], Y: [], Z: []})  # alternating strokes
    waving: list[Stroke] = field(default_factory=list)  # alternating side-to-side strokes of a wave
    announced: set = field(default_factory=set)  # IN_PROGRESS already sent, keyed by attempt
    wave_done_at: float = float("-inf")  # when a wave last completed: swings begun before it were part of it
    raised_since: float | None = None  # when the hand last went up above the head
    raised_done: bool = False
    slow_since: float | None = None  # since when the raised hand has been moving slowly
    clear_since: float | None = None  # since when the raised hand has been up and clear of the head
    at_head_since: float | None = None  # since when the raised hand has been at the head (or low)
    squat_watch: Stroke | None = None  # a push of both hands from hanging: is the body about to squat?

    last: dict[int, Stroke] = field(default_factory=dict)  # per axis: the last stroke judged
    jitter: dict[int, Stroke] = field(default_factory=dict)  # per axis: a reversal too brief to judge, held back
    settled: dict[int, Sample] = field(default_factory=dict)  # per axis: start of a swipe completed while under way

    def __post_init__(self) -> None:
        r = self.rules
        self.strokes = {a: AxisStrokes(a, r.stroke_hysteresis_mm, r.stroke_stop_s) for a in (X, Y, Z)}
        self.rhythm = Rhythm(r)

    def joined(self, stroke: Stroke) -> list[Stroke]:
        """The strokes to judge. A reversal of a frame or two is held back: a tracker's jitter or a
        quick swing? When the hand then goes on the way it went before, beyond where it turned, it
        was jitter: the stroke continues that one, which is taken back from the runs and pending
        swipes it joined. When the hand only comes back about as far after a reversal of at least
        `oscillation_min_travel_mm` (a wave's swing seen in two frames), it was a motion: both are
        judged, in order."""
        axis = stroke.axis
        jitter = self.jitter.pop(axis, None)
        if stroke.duration <= self.rules.stroke_min_reversal_s:
            self.jitter[axis] = stroke
            return []
        before = self.last.get(axis)
        self.last[axis] = stroke
        if not _around(jitter, before, stroke):
            return [stroke]
        if (jitter.travel >= self.rules.oscillation_min_travel_mm and stroke.direction * float(
                stroke.end.p[axis] - before.end.p[axis]) < self.rules.stroke_hysteresis_mm):
            return [jitter, stroke]
        merged = _merged(before, jitter, stroke)
        for run in (self.chains[axis], self.waving):
            if run and run[-1] is before:
                run.pop()
        if self.pending.get(axis) is before:
            del self.pending[axis]
        self.last[axis] = merged
        return [merged]

    def sample(self, t: float, p: np.ndarray, shoulder: float, face: np.ndarray, world: Vec3, body_vy: float,
               after_gap: bool = False) -> Sample:
        """The new sample with its velocity over the speed window, kept in a short history; `after_gap`:
        the hand was found again where it could not be followed (as after `track_gap_s` unseen)."""
        window = self.rules.speed_window_s
        last = self.samples[-1] if self.samples else None
        joined = last is not None and t - last.t <= self.rules.track_gap_s and not after_gap
        since = last.seen_since if joined else t
        ref = None
        for q in reversed(self.samples):
            if q.seen_since != since and ref is not None:
                break  # measured within the hand's unbroken run of samples, not diluted across a gap
            if ref is not None and ref.t - q.t > window:
                break  # nor across frames missing in it: measured over what came after them
            ref = q
            if t - q.t >= window or q.seen_since != since:
                break  # the first sample after a gap: the average speed across it, a lower bound
        v = (p - ref.p) / (t - ref.t) if ref is not None and t > ref.t else np.zeros(3)
        s = Sample(t, p, v, shoulder, face, world, body_vy, since)
        self.samples.append(s)
        while self.samples and t - self.samples[0].t > _HISTORY_S:
            self.samples.popleft()
        return s


class GestureRecognizer:
    """Feed `update()` once per frame; it returns the gesture events of that frame."""

    def __init__(self, rules: GestureRules | None = None,
                 dictionary: Mapping[str, GestureType] | None = None) -> None:
        self.rules = rules if rules is not None else GestureRules()
        self.dictionary = dict(OPENISS_DICTIONARY if dictionary is None else dictionary)
        unknown = set(self.dictionary) - set(CANONICAL_GESTURES)
        if unknown:
            raise ValueError(f"unknown gesture names {sorted(unknown)}; expected some of {', '.join(CANONICAL_GESTURES)}")
        self.reset()

    @property
    def body_measured(self) -> bool:
        """Does a skeleton give the body (torso or head) now, rather than an estimate from the hands?"""
        return self._body.measured

    def size(self, s: Sample) -> float:
        """The performer's size relative to the adult the distance thresholds are stated for."""
        return self.rules.size(s.head)

    def reset(self) -> None:
        """Forget every hand and the body (a new performance)."""
        self._body = BodyReference(self.rules)
        self._tracks: dict[int, _HandTrack] = {}
        self._last_t = float("-inf")
        self._mirrored = True

    def update(self, t: float, hands: Sequence[Hand], body: Mapping[str, Vec3] | None = None,
               mirrored: bool = True) -> list[Gesture]:
        """One frame: `t` seconds, hands in world mm, optional body points ("torso", "head").

        `mirrored` says whether +x is the performer's right (a mirrored image) or left; swipe
        directions are reported from the performer's point of view.
        """
        if t < self._last_t:  # the stream started again (a looping clip): a new performance
            self.reset()
        self._last_t, self._mirrored = t, mirrored
        live = [h for h in hands if h.in_view]
        events: list[Gesture] = []
        gone = {h.id for h in hands if not h.in_view}
        gone |= {i for i, tr in self._tracks.items() if t - tr.last_seen > self.rules.forget_after_s}
        for hid in gone:
            track = self._tracks.pop(hid, None)
            if track is not None:  # a swipe just before the hand left the view still counts
                _Hand(self, track, track.hand, t, mirrored, events, self._tracks).flush(gone=True)
        frame = self._body.update(t, {h.id: np.asarray(h.position, float) for h in live}, body or {})
        seen = {h.id for h in live}
        for h in live:
            track, refound = self._tracks.get(h.id), None
            if track is None:
                refound = self._refound(h, t, seen)
                track = self._tracks[h.id] = refound or _HandTrack(self.rules, h)
            track.hand, track.last_seen = h, t
            s = track.sample(t, np.asarray(h.position, float) - frame.torso, frame.shoulder_y - frame.torso[1],
                             frame.head - frame.torso, h.position, frame.vy, after_gap=refound is not None)
            _Hand(self, track, h, t, mirrored, events, self._tracks).step(s)
        for hid, track in self._tracks.items():
            if hid not in seen:  # unseen this frame: its pending swipes still come due
                _Hand(self, track, track.hand, t, mirrored, events, self._tracks).resolve_all(in_view=False)
        return events

    def _refound(self, hand: Hand, t: float, seen: set[int]) -> _HandTrack | None:
        """The track that a new hand continues, if any: the one on its side unseen now and last seen
        within `track_gap_s`. An arm has one hand; a depth tracker outrun by a flick (a whole arm faster
        than its gate) finds it again as a new one. The track goes on after a gap: where the hand was
        meanwhile is unknown, so the jump is no measured motion (a wave's turn counts; no swipe up or
        down spans it)."""
        if hand.side is Side.UNKNOWN:
            return None
        for hid, track in self._tracks.items():
            if hid not in seen and track.hand.side is hand.side and t - track.last_seen <= self.rules.track_gap_s:
                return self._tracks.pop(hid)
        return None

    def finish(self) -> list[Gesture]:
        """The stream ended (a clip's last frame): swipes still waiting to be confirmed complete, as
        when a hand leaves the view, at the last frame's time. A stroke still under way is not
        judged (ended early, an arm dropping to rest would look like a swipe down). Then a new
        performance. A hand already out of sight at the end is gone, as if it were lost."""
        events: list[Gesture] = []
        for track in self._tracks.values():
            _Hand(self, track, track.hand, self._last_t, self._mirrored, events, self._tracks).flush(
                gone=track.last_seen < self._last_t)
        self.reset()
        return events


class _Hand:
    """The rules applied to one hand for one frame (a short-lived helper, so the state stays in _HandTrack)."""

    def __init__(self, rec: GestureRecognizer, track: _HandTrack, hand: Hand, t: float,
                 mirrored: bool, events: list[Gesture], tracks: Mapping[int, _HandTrack]) -> None:
        self.rec, self.r, self.tr, self.hand, self.t = rec, rec.rules, track, hand, t
        self.mirrored, self.events = mirrored, events
        self.others = [other for other in tracks.values() if other is not track]

    # --- events -------------------------------------------------------------------------------
    def emit(self, name: str, state: GestureState, confidence: float, at: Sample) -> bool:
        """Report a gesture; a COMPLETE inside the refractory period is swallowed (returns False)."""
        native = self.rec.dictionary.get(name)
        if native is None:
            return False
        if state is GestureState.COMPLETE:
            # the refractory period swallows a stroke's return, not the hand held up where a swipe up took it
            held_up = name == "hand_raise" and self.tr.last_complete == "swipe_up"
            if self.t < self.tr.refractory_until and not held_up:
                return False
            self.tr.refractory_until = self.t + self.r.refractory_s
            self.tr.last_complete = name
            self.tr.pending.clear()
        self.events.append(Gesture(native, state, tuple(float(c) for c in at.world), self.hand.id,
                                   self.hand.side, float(np.clip(confidence, 0.0, 1.0)), self.t))
        return True

    def announce(self, name: str, key: object, confidence: float, at: Sample) -> None:
        """IN_PROGRESS, once per attempt (`key` names the attempt, e.g. the stroke's start time)."""
        if (name, key) not in self.tr.announced and self.t >= self.tr.refractory_until:
            if len(self.tr.announced) >= 64:  # attempts that old are long over
                self.tr.announced.clear()
            self.tr.announced.add((name, key))
            self.emit(name, GestureState.IN_PROGRESS, confidence, at)

    # --- one frame ----------------------------------------------------------------------------
    def step(self, s: Sample) -> None:
        for axis in (X, Y, Z):
            done = self.tr.strokes[axis].update(s)
            judged = self.tr.joined(done) if done is not None else []
            for i, stroke in enumerate(judged):
                reversed_ = i < len(judged) - 1 or self.tr.strokes[axis].direction != 0
                if axis == Z:
                    self.click(stroke)
                else:
                    self.stroke_ended(stroke, reversed_)
        self.rhythmic_wave(s)
        self.swipe_under_way()
        self.resolve_all()
        self.click_under_way()
        self.squat_watched()
        self.hand_raise(s)

    def resolve_all(self, in_view: bool = True) -> None:
        for axis in (X, Y):
            self.resolve_pending(axis, in_view)

    def flush(self, gone: bool) -> None:
        """The hand is gone (or the stream ended): its pending swipes are complete, nothing followed
        them. A swipe down whose hand is gone was the arm going back to rest, where a depth tracker
        loses the hand in the body: it is dropped."""
        for stroke in list(self.tr.pending.values()):
            if gone and _drop(stroke):
                continue
            self.confirm(stroke)
        self.tr.pending.clear()

    def core(self, stroke: Stroke) -> Stroke:
        r = self.r
        return stroke.core(r.stroke_core_speed_fraction, r.stroke_core_speed_mm_s, r.track_gap_s)

    def seen_throughout(self, stroke: Stroke) -> bool:
        """Was the hand seen without a gap from a while before the stroke to just after it? A hand
        found mid-rise may be lifting from a rest where a depth tracker could not tell it from the
        body; one lost during or at the end of a drop may be going back there."""
        since = stroke.start.seen_since
        if stroke.start.t - since < self.r.vertical_swipe_seen_before_s or stroke.end.seen_since != since:
            return False
        after = next((q for q in self.tr.samples if q.t > stroke.end.t), None)
        return after is None or after.seen_since == since

    def at_head(self, s: Sample) -> bool:
        """Is the hand at the head (on it, at the eyes, behind it), not clear of it?"""
        return float(np.linalg.norm(s.p - s.face)) < self.r.raise_clear_of_head_mm * self.rec.size(s)

    # --- swipes and waves ---------------------------------------------------------------------
    def swipe_name(self, stroke: Stroke) -> str:
        if stroke.axis == Y:
            return "swipe_up" if stroke.direction > 0 else "swipe_down"
        towards_right = (stroke.direction > 0) == self.mirrored
        return "swipe_right" if towards_right else "swipe_left"

    def swipe_like(self, stroke: Stroke) -> bool:
        """Fast and dominant along its axis, with the hand up from rest and the body steady
        (travel checked apart); judged on the stroke's core."""
        r = self.r
        core = self.core(stroke)
        if stroke.axis == Y:
            # judged whole: a vertical stroke that starts or ends at rest is the arm lifting or dropping,
            # one that starts or ends at the head is a hand going there (goggles, hands on the head)
            lowest = stroke.lowest
            if not self.seen_throughout(stroke) or self.at_head(stroke.start) or self.at_head(stroke.end):
                return False
            # an arm thrown up or down as the body bends or kicks: the head moves relative to the torso
            if self.head_moved(stroke) > self.r.swipe_vertical_max_head_move_mm * self.rec.size(stroke.start):
                return False
        else:
            lowest = core.lowest
        return (core.peak_speed >= r.swipe_min_peak_speed_mm_s and self.sweep_dominance(core) >= r.swipe_dominance
                and self.raised(core, lowest) and core.duration <= r.swipe_max_duration_s
                and core.body_speed <= r.steady_body_max_vertical_speed_mm_s and self.body_steady(stroke))

    def sweep_dominance(self, core: Stroke) -> float:
        """The core's dominance, but for a sweep sideways that does not fall, the hand up
        (`swipe_level_dominance`): a whole arm swinging about its shoulder, from in front to the side or
        across the body, brings the hand back towards the body's plane as it goes, up to as far as it
        sweeps across. Depth forwards (-z, towards the camera), back beyond that, or behind the torso's
        plane still counts."""
        rise = core.rise
        if (core.axis != X or core.travel < self.r.swipe_level_dominance * -rise
                or core.lowest < self.r.active_min_height_mm):
            return core.dominance
        back = float(core.end.p[Z] - core.start.p[Z])
        depth = max(back - core.travel, float(core.end.p[Z]), 0.0) if back > 0 else -back
        return core.travel / max(abs(rise), depth, 1.0)

    def raised(self, stroke: Stroke, lowest: float) -> bool:
        """Is the hand up from rest throughout the stroke? Above the rest line; or, sweeping sideways,
        down to waist height when it sweeps outwards and ends far out on its own side: the arm is
        then held away from the body, as a hanging arm or one swinging across the body to balance
        a kick or a step never is."""
        r = self.r
        if lowest >= r.active_min_height_mm:
            return True
        k = self.rec.size(stroke.start)
        return lowest >= r.swipe_low_min_height_mm * k and self.out_to(stroke, r.swipe_low_min_reach_mm * k)

    def out_to(self, stroke: Stroke, reach_mm: float) -> bool:
        """Does the sideways `stroke` sweep outwards, ending at least `reach_mm` out from the spine on
        its hand's own side?"""
        if stroke.axis != X or self.hand.side is Side.UNKNOWN:
            return False
        outwards = self.outwards()
        return stroke.direction == outwards and outwards * stroke.end.p[X] >= reach_mm

    def outwards(self) -> int:
        """The direction along x away from the body on the hand's own side (its side known)."""
        return (1 if self.hand.side is Side.RIGHT else -1) * (1 if self.mirrored else -1)

    def sure_swipe(self, stroke: Stroke) -> bool:
        """A swipe that is no wind-up, needing no wait for what follows: it starts from rest (a swipe
        wound up, or a wave's swing, starts with the hand moving) in front of the body, sweeps outwards
        into the arm's reach on its own side (no further to go that way; a wind-up for a swipe across
        the body also ends there, but after the hand swung up or across first, or drawn out from in
        front of its shoulder), as far as an adult's swipe (a child's shorter stroke may be a wind-up
        that reaches as far for her size), and no other hand moves meanwhile (arms balancing a kick,
        or spreading together)."""
        r = self.r
        k = self.rec.size(stroke.start)
        start = stroke.start
        if (self.core(stroke).travel < r.swipe_min_travel_mm
                or not self.out_to(stroke, r.swipe_sure_reach_mm * k) or not self.still_before(start, (X,))
                or stroke.direction * float(start.p[X]) > r.swipe_sure_start_mm * k):
            return False
        for other in self.others:
            during = _during(other, stroke)
            if during and max(float(np.linalg.norm(q.p - during[0].p)) for q in during) >= (
                    r.swipe_comparable_ratio * stroke.travel):
                return False
        return True

    def still_before(self, start: Sample, axes: tuple[int, ...]) -> bool:
        """Was the hand seen throughout `swipe_rest_s` before `start`, moving less than `swipe_rest_mm`
        along `axes` (for the performer's size)?"""
        r = self.r
        if start.t - start.seen_since < r.swipe_rest_s:
            return False
        before = np.array([q.p for q in self.tr.samples if start.t - r.swipe_rest_s <= q.t <= start.t])
        if not len(before):  # none: older than the history kept
            return False
        spread = before[:, list(axes)].max(axis=0) - before[:, list(axes)].min(axis=0)
        return float(spread.max()) < r.swipe_rest_mm * self.rec.size(start)

    def swipe_under_way(self) -> None:
        """A sideways swipe is announced while its stroke is still under way, as soon as it is one; a
        sure one (`sure_swipe`) completes there once it settles, before the hand has stopped. (A
        vertical stroke is judged whole, once it ends: one under way may yet drop to rest.)"""
        current = self.tr.strokes[X].current()
        if (current is None or len(current.samples) < 2 or self.tr.settled.get(X) is current.start
                or self.waving(current) or not self.is_swipe(current)):
            return
        name, confidence = self.swipe_name(current), self.swipe_confidence(current)
        self.announce(name, current.start.t, confidence, current.end)
        settled = current.direction * float(current.end.v[X]) <= self.r.swipe_settle_fraction * current.peak_speed
        if (settled and X not in self.tr.pending and self.sure_swipe(current)
                and self.emit(name, GestureState.COMPLETE, confidence, current.end)):
            self.tr.settled[X] = current.start

    def waving(self, stroke: Stroke) -> bool:
        """Would `stroke` be the third (or later) of quick alternating strokes: a wave's, never a swipe?"""
        chain = self.tr.chains[stroke.axis]
        return (len(chain) >= 2 and chain[-1].direction == -stroke.direction
                and stroke.start.t - chain[-1].end.t <= self.r.oscillation_max_gap_s
                and self.wave_paced(stroke))

    def wave_paced(self, stroke: Stroke) -> bool:
        """Is the stroke as quick as a wave's swing and does it reach a wave's height (in front of the chest
        or higher)? Slower or lower strokes back and forth are swipes repeated with their wind-ups."""
        return (stroke.duration <= self.r.wave_max_stroke_s and stroke.highest >= stroke.start.shoulder
                - self.r.wave_max_below_shoulder_mm * self.rec.size(stroke.start))

    def is_swipe(self, stroke: Stroke) -> bool:
        core = self.core(stroke)
        return ((core.travel >= self.swipe_travel_mm(stroke) and not self.brought_across(stroke) and self.swipe_like(stroke))
                or self.swept_up_across(stroke)) and not self.mirrored_by_other_hand(core, along=True)

    def across_from_hanging(self, stroke: Stroke) -> bool:
        """Does the sideways `stroke` start from the hanging arm (below `active_min_height_mm`) and go
        across the body, towards the other side?"""
        return (stroke.axis == X and self.hand.side is not Side.UNKNOWN and stroke.direction != self.outwards()
                and float(stroke.start.p[Y]) < self.r.active_min_height_mm)

    def brought_across(self, stroke: Stroke) -> bool:
        """Did the hand come across the body from hanging to stop in front of the chest: below the shoulders
        and short of `swipe_across_min_reach_mm` in front? However fast, that is no swipe (MSRC-12 p03 winds up
        each push right so, ending 180-260 mm below the shoulders, and 15 % faster the wind-up passed a swipe's
        speed; p10 changing weapon too): a swipe rising across reaches out to the screen (`swept_up_across`),
        and one that sweeps up high across (UTD-MHAD subject 4's, ending 100 mm above the shoulders) is
        judged as any other."""
        end = stroke.end
        return self.across_from_hanging(stroke) and float(end.p[Y]) < float(end.shoulder) and not self.out_in_front(stroke)

    def out_in_front(self, stroke: Stroke) -> bool:
        """Does the stroke end `swipe_across_min_reach_mm` or more in front of the torso (for the performer's size)?"""
        return -float(stroke.end.p[Z]) >= self.r.swipe_across_min_reach_mm * self.rec.size(stroke.start)

    def swept_up_across(self, stroke: Stroke) -> bool:
        """A swipe across the body straight from the hanging arm: the hand, still at its side, rises across
        the spine in one diagonal out to an imaginary screen (Kinder-Gator's child p106 swipes so; too
        upward for `swipe_dominance`). Judged whole, from where the arm hung, as the start of the arc rises
        before it gathers speed sideways: a swipe's travel sideways, fast, ending above the rest line, no
        higher than the chin (`above_chin`) and `swipe_across_min_reach_mm` out in front. A hand brought to
        the chest (a push's wind-up) ends closer to the body, one reaching over the shoulder higher; arms
        pumping as the body runs were not still before. It waits for a stroke back, which wins if
        stronger: the rise wound it up (`wound_up`)."""
        r = self.r
        if not self.across_from_hanging(stroke):
            return False
        start, end = stroke.start, stroke.end
        if not (r.active_min_height_mm <= float(end.p[Y]) and stroke.direction * float(end.p[X]) >= 0
                and self.out_in_front(stroke)
                and stroke.travel >= self.swipe_travel_mm(stroke) and stroke.duration <= r.swipe_max_duration_s):
            return False  # the cheap tests first: this runs every frame a stroke is under way
        core = self.core(stroke)
        return (core.peak_speed >= r.swipe_min_peak_speed_mm_s and not self.above_chin(end)
                and core.body_speed <= r.steady_body_max_vertical_speed_mm_s and self.still_before(start, (X, Y, Z))
                and self.body_steady(stroke) and not self.arms_swinging(stroke))

    def swipe_travel_mm(self, stroke: Stroke) -> float:
        """How far a swipe goes at least: sideways for the performer's size, up or down an adult's."""
        return self.r.swipe_min_travel_mm * (self.rec.size(stroke.start) if stroke.axis == X else 1.0)

    def mirrored_by_other_hand(self, stroke: Stroke, along: bool = False) -> bool:
        """Did another hand make the opposite motion at the same time (a clap, arms spreading)? With
        `along`, or the same motion (the body turning, both arms swinging the same way to balance a
        kick)? Swipes and waves are made by one hand, the other still or elsewhere."""
        for other in self.others:
            during = _during(other, stroke)
            if len(during) >= 2:
                moved = [stroke.direction * float(q.p[stroke.axis] - during[0].p[stroke.axis]) for q in during]
                limit = self.r.swipe_comparable_ratio * stroke.travel
                if -min(moved) >= limit or (along and max(moved) >= limit):
                    return True
        return False

    def comparable(self, follower: Stroke, first: Stroke) -> bool:
        """A stroke the other way, as fast, dominant and nearly as long: `first` was no swipe on its own."""
        return (follower.direction == -first.direction and self.swipe_like(follower)
                and follower.travel >= self.r.swipe_comparable_ratio * first.travel)

    @staticmethod
    def stroke_confidence(core: Stroke, min_travel_mm: float, min_peak_speed_mm_s: float, dominance: float,
                          min_dominance: float) -> float:
        """How far a stroke's core clears a gesture's travel, speed and dominance thresholds."""
        return _confidence(_margin(core.travel, min_travel_mm), _margin(core.peak_speed, min_peak_speed_mm_s),
                           _margin(dominance, min_dominance))

    def swipe_confidence(self, stroke: Stroke) -> float:
        core = self.core(stroke)
        return self.stroke_confidence(core, self.swipe_travel_mm(stroke), self.r.swipe_min_peak_speed_mm_s,
                                      self.sweep_dominance(core), self.r.swipe_dominance)

    def stroke_ended(self, stroke: Stroke, reversed_: bool) -> None:
        chain = self.tr.chains[stroke.axis]
        _extend(chain, stroke, stroke.travel >= self.r.oscillation_min_travel_mm
                and stroke.dominance >= self.r.oscillation_min_dominance and stroke.lowest >= self.r.active_min_height_mm
                and stroke.end.seen_since == stroke.start.seen_since,  # not lost on the way
                self.r.oscillation_max_gap_s)
        if self.tr.settled.get(stroke.axis) is stroke.start:  # completed while under way
            # completing early does not shorten its refractory period (the hand's return is no gesture):
            # it runs as if the swipe had been confirmed `swipe_confirm_s` after its stroke, as any other
            self.tr.refractory_until = max(self.tr.refractory_until,
                                           stroke.end.t + self.r.swipe_confirm_s + self.r.refractory_s)
            if stroke.axis == X:
                self.wave(stroke, reversed_)
            return
        pending = self.tr.pending.pop(stroke.axis, None)
        # a comparable stroke the other way after a pending swipe: of the two the stronger is the swipe,
        # the other its wind-up or its return; but a weaker return that turns straight into yet another
        # stroke after a swipe at a wave's pace makes a back-and-forth (a wave's first swings), and neither
        # is. After a slower or lower swipe the return's turn is the hand bouncing at the body (MSRC-12's
        # p08) or a tracker's glitch: the swipe waits to see the return go on and prove the stronger
        # (`cut_short`). Otherwise the first is confirmed now, unless a glitch cut a stroke back short: it
        # waits as well, the stroke itself no swipe meanwhile (a turn after all leaves it a short stroke
        # back, a return).
        follows = pending is not None and self.comparable(stroke, pending)
        stronger = follows and self.strength(stroke) > self.strength(pending)
        bounced = follows and not stronger and not self.wave_paced(pending)  # a return, then no wave's swing
        glitched = pending is not None and not follows and self.glitched_back(pending, stroke)
        held = reversed_ and (bounced or glitched)
        if held:
            self.tr.pending[stroke.axis] = pending
        elif pending is not None and (not follows or not (stronger or reversed_)) and not self.wound_up(pending, stroke):
            self.confirm(pending)
        place = len(chain) if chain and chain[-1] is stroke else 1
        # the third of quick alternating strokes at a wave's height is a wave's; a slower or lower sweep is not
        waving = place > 2 and self.wave_paced(stroke)
        if not held and not waving and self.is_swipe(stroke) and (not follows or stronger):
            self.tr.pending[stroke.axis] = stroke
            self.announce(self.swipe_name(stroke), stroke.start.t, self.swipe_confidence(stroke), stroke.end)
        if stroke.axis == X:
            self.wave(stroke, reversed_)

    def resolve_pending(self, axis: int, in_view: bool = True) -> None:
        """Complete a swipe once it is clear that no comparable stroke the other way follows it; a
        swipe down only while its hand is in view (see `flush`)."""
        pending = self.tr.pending.get(axis)
        if pending is None:
            return
        due = pending.end.t + self.r.swipe_confirm_s
        rose_across = self.swept_up_across(pending)
        if rose_across:  # the hand may pause there before the swipe back that the rise wound up
            due = pending.end.t + max(self.r.swipe_confirm_s, self.r.swipe_rest_s)
        elif self.sure_swipe(pending):  # at once, or when the refractory period ends if sooner than `due`
            due = min(due, max(pending.end.t, self.tr.refractory_until))
        if self.t < due:
            return
        if not in_view and _drop(pending):
            return
        current = self.tr.strokes[axis].current()
        if current is not None and current.direction == -pending.direction and (
                self.swipe_like(current) or self.turned_into(pending, current) or rose_across):
            # a fast stroke the other way, or one the hand turned straight into, is under way: wait for it
            # (after a rise across the body, any stroke back: the rise may have wound up a swipe back)
            return
        if self.cut_short(pending, current):
            return
        del self.tr.pending[axis]
        if not self.dropped_on(pending, current):
            self.confirm(pending)

    def glitched_back(self, pending: Stroke, back: Stroke) -> bool:
        """Was `back`, the stroke the hand turned straight into from `pending`, cut short at a swipe's speed
        (`swipe_min_peak_speed_mm_s`)? A hand slows before it turns, a tracker's glitch does not (MSRC-12
        p03's skeleton hand jumped back for one frame in a 6 m/s push). Speeds lag over the speed window,
        so a quick real turn may pass too: waiting for it costs at most `stroke_min_reversal_s`."""
        return (back.direction == -pending.direction and back.start.t <= pending.end.t
                and back.direction * float(back.end.v[back.axis]) >= self.r.swipe_min_peak_speed_mm_s)

    def cut_short(self, pending: Stroke, current: Stroke | None) -> bool:
        """May the stroke back from `pending`, glitched (`glitched_back`) or a comparable return that turned,
        yet go on and prove the stronger (`joined`)? While the hand turned from it no longer than
        `stroke_min_reversal_s` ago, or goes on its way again after such a reversal (a glitched stroke:
        the two together so far like a swipe)."""
        last, jitter = self.tr.last.get(pending.axis), self.tr.jitter.get(pending.axis)
        if current is None or last is None:
            return False
        returned = self.comparable(last, pending)
        if not (returned or self.glitched_back(pending, last)):
            return False
        if current.direction == pending.direction:
            return current.duration <= self.r.stroke_min_reversal_s
        return jitter is not None and (returned or self.swipe_like(_merged(last, jitter, current)))

    def dropped_on(self, pending: Stroke, current: Stroke | None) -> bool:
        """Did the hand, after a stroke down, turn back for a frame or two (a tracker's jitter, held back)
        and then go on down to rest (below `active_min_height_mm`)? Then the strokes are one (`joined`), an
        arm dropping to rest that the glitch cut short above the rest line, no swipe down."""
        return (_drop(pending) and _around(self.tr.jitter.get(pending.axis), pending, current)
                and float(current.end.p[Y]) < self.r.active_min_height_mm)

    def above_chin(self, s: Sample) -> bool:
        """Is the hand higher than a swipe across the body ends (`swipe_across_max_above_shoulder_mm`), or at
        the head?"""
        limit = s.shoulder + self.r.swipe_across_max_above_shoulder_mm * self.rec.size(s)
        return float(s.p[Y]) > limit or self.at_head(s)

    def wound_up(self, rise: Stroke, back: Stroke) -> bool:
        """Did a rise across the body wind up `back`, a stronger stroke back, swipe or not (a throw, a
        push, a roll of the arms)?"""
        return (back.direction == -rise.direction and self.swept_up_across(rise)
                and self.strength(back) > self.strength(rise))

    def confirm(self, stroke: Stroke) -> None:
        """Complete a pending swipe, unless the body has rocked forward or back meanwhile (a kick's
        or a lunge's torso may move only after the arm's swing for balance), or a rise across the body
        went on up (reaching over the shoulder)."""
        if self.swept_up_across(stroke) and self.above_chin(self.tr.samples[-1]):
            return
        if self.body_steady(stroke):
            self.emit(self.swipe_name(stroke), GestureState.COMPLETE, self.swipe_confidence(stroke), stroke.end)

    def body_steady(self, stroke: Stroke) -> bool:
        """Did the torso keep from moving towards or away from the camera (a kick, a lunge, a step) from
        `steady_body_depth_window_s` before the stroke until now (distances for the performer's size)?
        Told only with a skeleton: a body estimated from the hands follows the hands."""
        r = self.r
        return not self.rec.body_measured or lurch(self.tr.samples, stroke.start.t, r.steady_body_depth_window_s) <= (
            r.steady_body_max_depth_move_mm * self.rec.size(stroke.start))

    def turned_into(self, stroke: Stroke, current: Stroke) -> bool:
        """Did the hand turn from `stroke` straight into `current` (no hold between them), not longer
        ago than a swipe lasts, and is `current` heading like a sideways swipe but for its speed (the
        hand up, moving sideways `swipe_dominance` times faster than up or down now)? A wind-up turns
        straight into its swipe, which may take a while to gather speed; an arm dropping back to rest
        after a swipe goes down as much as back. After a stroke that rose as far as a swipe travels
        (an arm swung up across the body in an arc), the hand loops up at the turn: rising then is no
        drop to rest, only going down counts."""
        vy = float(current.end.v[Y])
        if stroke.rise >= self.swipe_travel_mm(stroke):
            vy = min(vy, 0.0)
        return (current.axis == X and current.start.t <= stroke.end.t
                and current.duration <= self.r.swipe_max_duration_s and self.raised(current, current.lowest)
                and abs(float(current.end.v[X])) >= self.r.swipe_dominance * abs(vy))

    def strength(self, stroke: Stroke) -> float:
        """How far and how fast the stroke's core goes: travel times mean speed (mm^2/s). Of a swipe and
        its wind-up or its return, the swipe is the stronger: the other is slower, shorter or both."""
        core = self.core(stroke)
        return core.travel ** 2 / max(core.duration, 1e-3)

    def wave_stroke(self, stroke: Stroke, opening: bool) -> bool:
        """One swing of a wave: quick, side to side, the hand up in front of the chest or higher (or,
        `opening` the wave, swinging up into it), not lost on the way, and the other hand elsewhere
        (distances for the performer's size)."""
        r = self.r
        k = self.rec.size(stroke.start)
        return (self.wave_paced(stroke) and stroke.travel >= r.wave_min_amplitude_mm * k
                and stroke.dominance >= r.wave_min_dominance
                and (stroke.lowest >= stroke.start.shoulder - r.wave_arc_below_shoulder_mm * k
                     or opening and self.swung_up_into_wave(stroke))
                and stroke.end.seen_since == stroke.start.seen_since
                and self.hands_apart(stroke) >= r.wave_min_hands_apart_mm * k
                and self.tilt(stroke) <= r.wave_max_tilt_deg
                and not self.mirrored_by_other_hand(stroke))

    def swung_up_into_wave(self, stroke: Stroke) -> bool:
        """Is the swing an arm swinging up into a wave: rising (its lowest point where it starts, but for
        a tracker's jitter) from above the rest line (`active_min_height_mm`)? A whole arm lifted out to
        the side starts waving so, lower than any swing of its arc later; an arm lifted straight from
        hanging, or sweeping low across the front, is not waving yet."""
        lowest = stroke.lowest
        return lowest >= self.r.active_min_height_mm and float(stroke.start.p[Y]) - lowest <= self.r.stroke_hysteresis_mm

    @staticmethod
    def head_moved(stroke: Stroke) -> float:
        """How far the head moved relative to the torso during the stroke, mm (0 without a skeleton's head)."""
        face = np.array([q.face for q in stroke.samples])
        return float(np.max(np.linalg.norm(face - face[0], axis=1)))

    @staticmethod
    def tilt(stroke: Stroke) -> float:
        """How far the body leaned during the stroke: the largest angle, degrees, between straight up and
        the line from the torso to the head (0 without a skeleton's head)."""
        face = np.array([q.face for q in stroke.samples])
        up = face[:, Y] / np.maximum(np.linalg.norm(face, axis=1), 1e-9)
        return float(np.degrees(np.arccos(np.clip(up.min(), -1.0, 1.0))))

    def hands_apart(self, stroke: Stroke) -> float:
        """How near the other hands came to this one during the stroke, mm (inf: no other hand)."""
        near = float("inf")
        for other in self.others:
            theirs = {round(q.t, 4): q.p for q in _during(other, stroke)}
            for q in stroke.samples:
                p = theirs.get(round(q.t, 4))
                if p is not None:
                    near = min(near, float(np.linalg.norm(q.p - p)))
        return near

    def wave(self, stroke: Stroke, reversed_: bool) -> None:
        """Count the swings of a wave: alternating wave strokes, each starting soon after the last."""
        run, gap = self.tr.waving, self.r.oscillation_max_gap_s
        _extend(run, stroke, self.wave_stroke(stroke, opening=not _continues(run, stroke, gap)), gap)
        if not run:
            return
        first = run[0]
        reversals = len(run) - 1 + int(reversed_)
        if first.start.t <= self.tr.wave_done_at:
            return
        k = self.rec.size(first.start)
        amplitude = float(np.median([s.travel for s in run]))
        top = max(s.highest - s.start.shoulder for s in run)
        if (amplitude < self.r.wave_min_typical_amplitude_mm * k or top < -self.r.wave_top_below_shoulder_mm * k
                or np.median([s.duration for s in run]) < self.r.wave_min_swing_s):
            return
        confidence = _confidence(_margin(amplitude, self.r.wave_min_typical_amplitude_mm * k),
                                 min(1.0, reversals / (2 * self.r.wave_min_reversals)))
        # one reversal is also a wind-up and its swipe: announced from two on
        self.wave_count(reversals, self.r.wave_min_reversals, max(1, self.r.wave_min_reversals - 1),
                        first.start.t, confidence, stroke.end)

    def rhythmic_wave(self, s: Sample) -> None:
        """A wave told by its rhythm (rhythm.py): swings too small for strokes, keeping a wave's time,
        with the other hand elsewhere and the body upright as for any wave."""
        rhythm, r = self.tr.rhythm, self.r
        swing = rhythm.update(s)
        if swing is None:
            return
        k = self.rec.size(swing.start)
        run = rhythm.add(swing, rhythm.in_time(swing, k) and self.tilt(swing) <= r.wave_max_tilt_deg
                         and self.hands_apart(swing) >= r.wave_min_hands_apart_mm * k)
        if not run or run[0].start.t <= self.tr.wave_done_at:
            return
        confidence = _confidence(min(1.0, len(run) / (2 * r.wave_rhythm_min_swings)))
        self.wave_count(len(run), r.wave_rhythm_min_swings, r.wave_rhythm_min_swings - 1, run[0].start.t,
                        confidence, swing.end)

    def wave_count(self, count: int, needed: int, announced_from: int, started: float, confidence: float,
                   end: Sample) -> None:
        """A wave of `count` swings (or reversals) begun at `started`: complete at `needed`, in progress
        from `announced_from`. A completion is noted (`wave_done_at`): the callers do not count the
        swings begun before it again."""
        if count >= needed:
            if self.emit("wave", GestureState.COMPLETE, confidence, end):
                self.tr.wave_done_at = self.t
        elif count >= announced_from:
            self.announce("wave", started, confidence, end)

    # --- click --------------------------------------------------------------------------------
    def click_like(self, stroke: Stroke) -> bool:
        """Fast towards the camera, ending far in front of the body at chest height or above and
        heading straight forward at the end (judged on the stroke's core, distances for the
        performer's size). Where the hand came from does not matter: from the chest or hanging."""
        r = self.r
        core = self.core(stroke)
        k = self.rec.size(stroke.start)
        end = core.end
        sideways = abs(float(end.p[X] - core.start.p[X]))
        return (stroke.direction < 0 and core.travel >= r.click_min_travel_mm * k
                and core.peak_speed >= r.click_min_peak_speed_mm_s
                and core.travel >= r.click_dominance * sideways
                and self.forward_enough(core, k)
                and self.ends_forward(core, r.click_end_mm * k) >= r.click_end_dominance
                and -float(end.p[Z]) >= r.click_min_reach_mm * k
                and float(end.p[Y]) >= end.shoulder - r.click_max_below_shoulder_mm * k
                and r.click_min_duration_s <= stroke.duration and core.duration <= r.click_max_duration_s
                and core.body_speed <= r.steady_body_max_vertical_speed_mm_s)

    def forward_enough(self, core: Stroke, k: float) -> bool:
        """Forward at least `click_min_forward_per_rise` of the rise, from the push's turn forward.
        Checked only once the cheaper tests pass: `click_under_way` asks every frame."""
        push = self.turned_forward(core, self.r.click_end_mm * k)
        return push.travel >= self.r.click_min_forward_per_rise * push.rise

    @staticmethod
    def turned_forward(core: Stroke, push_mm: float) -> Stroke:
        """The core from its first sample heading forward at least as fast as it rises, if the hand still
        travels `push_mm` forward from there (a push's last stretch); else the whole core. A push that
        follows a rise from hanging without a stop is judged as the push it ends in; an arm lifted from
        the side (to point, to start a swipe, to balance a kick) rises more than it comes forward from
        there, or comes forward less than that."""
        first = next((i for i, q in enumerate(core.samples) if core.direction * q.v[Z] >= q.v[Y]), 0)
        push = Stroke(core.axis, core.direction, core.samples[first:])
        return push if push.travel >= push_mm else core

    @staticmethod
    def ends_forward(stroke: Stroke, stretch_mm: float) -> float:
        """Over the stroke's last `stretch_mm` of forward travel: forward over sideways or vertical motion."""
        end = stroke.end.p
        start = next((q.p for q in reversed(stroke.samples) if q.p[Z] - end[Z] >= stretch_mm), stroke.start.p)
        d = np.abs(end - start)
        return float(d[Z] / max(d[X], d[Y], 1.0))

    def click_confidence(self, stroke: Stroke) -> float:
        r, core = self.r, self.core(stroke)
        return self.stroke_confidence(core, r.click_min_travel_mm, r.click_min_peak_speed_mm_s, core.dominance,
                                      r.click_dominance)

    def halted(self, stroke: Stroke) -> bool:
        """Did the hand nearly stop at the stroke's end (a push stops or comes back; a hand sweeping
        down past its furthest point does not)? Unseen just after the end, the next sample tells
        (its speed spans the gap)."""
        later = [q for q in self.tr.samples if q.t > stroke.end.t]
        soon = [q for q in later if q.t <= stroke.end.t + self.r.speed_window_s + 1e-6] or later[:1]
        return min(float(np.linalg.norm(q.v)) for q in (stroke.end, *soon)) <= self.r.click_halt_max_speed_mm_s

    def click(self, stroke: Stroke) -> None:
        """A push, unless it is an arm's swing: after two swings back and forth, with another arm
        swinging back, or both arms rising forward from the sides together."""
        chain = self.tr.chains[Z]
        _extend(chain, stroke, stroke.travel >= self.r.oscillation_min_travel_mm * self.rec.size(stroke.start)
                and stroke.duration <= self.r.swing_max_stroke_s, self.r.oscillation_max_gap_s)
        if len(chain) >= 4 or not (self.click_like(stroke) and self.halted(stroke)) or self.arms_swinging(stroke):
            return
        if self.arms_swinging(stroke, together=True):
            if self.rec.body_measured:  # a squat or a jump, if the body sinks or rises soon: wait and see
                self.tr.squat_watch = stroke
            return
        self.emit("click", GestureState.COMPLETE, self.click_confidence(stroke), stroke.end)

    def squat_watched(self) -> None:
        """Both hands pushed forward from hanging at the sides with a skeleton to tell: a push if the
        body stayed up until `click_squat_watch_s` after it (a squat's arms rise before the body
        sinks), else the arms' swing of a squat or jump."""
        stroke = self.tr.squat_watch
        if stroke is None or self.t < stroke.end.t + self.r.click_squat_watch_s:
            return
        self.tr.squat_watch = None
        body_vy = [abs(q.body_vy) for q in self.tr.samples if q.t >= stroke.start.t]
        if max(body_vy) <= self.r.steady_body_max_vertical_speed_mm_s:
            self.emit("click", GestureState.COMPLETE, self.click_confidence(stroke), stroke.end)

    def arms_swinging(self, stroke: Stroke, together: bool = False) -> bool:
        """Did another hand swing back as this one came forward (running, walking)? With `together`,
        did it rise forward with it from hanging at the side (squatting, jumping; or pushing a button
        with both hands)?"""
        core = self.core(stroke)
        ratio = self.r.swipe_comparable_ratio
        advance = float(core.start.p[Z] - core.end.p[Z])  # how far this hand came forward
        hanging = (together and core.start.p[Y] - core.start.shoulder
                   <= -self.r.click_hanging_below_shoulder_mm * self.rec.size(core.start))
        for other in self.others:
            during = _during(other, core)
            if len(during) < 2:
                continue
            forward, up = during[0].p[Z] - during[-1].p[Z], during[-1].p[Y] - during[0].p[Y]
            if together:
                if hanging and forward >= ratio * advance and up >= ratio * advance:
                    return True
            elif forward <= -ratio * advance:
                return True
        return False

    def click_under_way(self) -> None:
        current = self.tr.strokes[Z].current()
        if current is not None and len(current.samples) > 1 and self.click_like(current):
            self.announce("click", current.start.t, self.click_confidence(current), current.end)

    # --- hand raise ---------------------------------------------------------------------------
    def hand_raise(self, s: Sample) -> None:
        """Up above the head and clear of it, then stopping (at the top of a lift or held there), or
        kept up and clear for `raise_hold_s` however it moves (passing the head for moments)."""
        r, tr = self.r, self.tr
        k = self.rec.size(s)
        above = float(s.p[Y]) - (s.head + r.raise_min_above_head_mm * k)
        clear = float(np.linalg.norm(s.p - s.face)) - r.raise_clear_of_head_mm * k  # < 0: at the head
        if above < 0 or clear < 0:
            tr.slow_since = None
            if tr.at_head_since is None:
                tr.at_head_since = s.t
            if above < 0 or s.t - tr.at_head_since >= r.raise_past_head_s:  # lowered, or put at the head
                tr.clear_since = None
            if above < -r.stroke_hysteresis_mm:  # lowered for real: the next raise counts again
                tr.raised_since, tr.raised_done = None, False
            return
        tr.at_head_since = None
        if tr.raised_since is None:
            tr.raised_since = s.t
        if tr.clear_since is None:
            tr.clear_since = s.t
        if tr.raised_done:
            return
        confidence = _confidence(_margin(above + r.raise_min_above_head_mm * k, r.raise_min_above_head_mm * k),
                                 _margin(clear + r.raise_clear_of_head_mm * k, r.raise_clear_of_head_mm * k))
        if float(np.linalg.norm(s.v)) > r.raise_max_speed_mm_s:
            tr.slow_since = None
        elif tr.slow_since is None:
            tr.slow_since = s.t
        stopped = tr.slow_since is not None and s.t - tr.slow_since >= r.raise_still_s
        steady = abs(s.body_vy) <= r.steady_body_max_vertical_speed_mm_s
        held = s.t - tr.clear_since >= r.raise_hold_s
        if s.t - tr.raised_since >= r.raise_min_up_s and (stopped or held) and steady:
            tr.raised_done = self.emit("hand_raise", GestureState.COMPLETE, confidence, s)
        else:
            self.announce("hand_raise", tr.raised_since, confidence, s)
