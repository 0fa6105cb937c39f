"""Who is who: a stable user id per person across frames, occlusions and crossings.

The segmenter finds the people of one frame; this module matches them to the people of the
frames before. Each person is followed by the centre of their main surface (mm) with a velocity,
so a performer hidden behind another while crossing is looked for where they were heading, and
depth keeps two performers apart as they pass (one in front of the other). The match with the
smallest total cost wins, within a gate that grows with the time unseen (or covering much of
the person's last mask); the cost is the distance
to the predicted centre (height counting half: arms move it) less a bonus for overlapping last
frame's mask, plus the change in height (the tall and the small one). A person hidden behind
another can show as two pieces: a piece close to a matched person's predicted place, at their
depth, joins that person.

Lifecycle, as hands: NEW on the first frame, TRACKING, then LOST once after `lost_timeout_s`
unseen. A person who comes back within `return_s` of being lost, about where they were lost and
no taller than they were, gets their id back. Ids are the smallest free ones (NiTE's way), so they fit the
uint8 label image.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from backends.engine.assignment import best_assignment
from backends.engine.segmentation import Person
from host import HandState


class PeopleOptions(BaseModel):
    """How people are told apart over time (mm, s)."""

    model_config = ConfigDict(extra="forbid")
    lost_timeout_s: float = Field(1.5, ge=0, description=(
        "a person unseen this long is LOST (longer than a crossing hides the one behind)"))
    max_speed_mm_s: float = Field(2500, gt=0, description="fastest plausible walk: gates matching across frames")
    match_slack_mm: float = Field(600, ge=0, description=(
        "matching distance allowed on top of max speed * time unseen (the centre of what is seen of "
        "someone jumps when an arm or the legs come into view or go out)"))
    match_max_gap_s: float = Field(0.5, gt=0, description="the gate stops growing after this long unseen")
    same_place_overlap: float = Field(0.3, ge=0, le=1, description=(
        "a person covering this share of someone's last mask may be them however far their centre "
        "moved (close to the camera, an arm coming into view moves it a lot)"))
    overlap_bonus_mm: float = Field(300, ge=0, description="cost taken off for covering all of last frame's mask")
    height_weight: float = Field(0.5, ge=0, description="cost per mm of change in height (the top of the person)")
    piece_width_mm: float = Field(450, gt=0, description=(
        "a further piece this close sideways to a matched person's predicted centre, at their depth, is theirs"))
    piece_depth_mm: float = Field(400, gt=0, description="... and this close in depth to that person")
    velocity_smoothing: float = Field(0.3, gt=0, le=1, description="weight of the newest velocity measurement")
    return_s: float = Field(5.0, ge=0, description=(
        "a person lost at most this long ago who comes back where they left gets their id back"))
    return_mm: float = Field(800, ge=0, description="where they left: this close (sideways and in depth) to where they were last seen")
    return_height_mm: float = Field(200, ge=0, description=(
        "a person coming back is no taller than they were seen by more than this (shorter is fine: "
        "someone coming into view shows only part of themselves at first)"))


@dataclass(eq=False)
class _Track:
    id: int
    centre: np.ndarray  # (x, y, z) mm where last seen
    velocity: np.ndarray  # mm/s in x and z (y: 0)
    top_mm: float
    seen: float
    mask: np.ndarray | None = None  # last frame's mask on the grid
    reported: bool = False
    tallest_mm: float = -np.inf  # the highest top seen: how tall they are, at least

    def predicted(self, t: float, max_gap_s: float) -> np.ndarray:
        return self.centre + self.velocity * min(t - self.seen, max_gap_s)


@dataclass(frozen=True)
class Tracked:
    """One person this frame: their id, state and, when seen in this frame, their segment's person."""

    id: int
    state: HandState
    person: Person | None  # None: not seen now (hidden, or LOST)
    centre: tuple[float, float, float]


@dataclass(frozen=True)
class _Gone:
    id: int
    centre: np.ndarray  # where last seen
    tallest_mm: float
    t: float  # when lost


class PeopleTracker:
    """People in, ids out: `update()` once per frame with that frame's people."""

    def __init__(self, options: PeopleOptions | None = None) -> None:
        self.options = options or PeopleOptions()
        self._tracks: list[_Track] = []
        self._gone: list[_Gone] = []  # lost recently: their id waits for them

    def update(self, t: float, people: list[Person]) -> list[Tracked]:
        """This frame's people with their ids: NEW, TRACKING, or LOST (once); people hidden for
        now are returned with `person` None and state TRACKING (their hands time out meanwhile)."""
        o = self.options
        self._gone = [g for g in self._gone if t - g.t <= o.return_s]
        matched = self._match(t, people)
        pieces = [p for p in people if p not in matched.values()]
        merged: dict[_Track, list[Person]] = {tr: [p] for tr, p in matched.items()}
        for piece in list(pieces):
            owner = self._owner(t, piece, matched)
            if owner is not None:
                merged[owner].append(piece)
                pieces.remove(piece)
        out: list[Tracked] = []
        for track, parts in merged.items():
            person = parts[0] if len(parts) == 1 else _union(parts)
            self._seen(track, t, person)
            out.append(self._report(track, person))
        for person in pieces:
            track = self._birth(t, person)
            out.append(self._report(track, person))
        for track in [tr for tr in self._tracks if tr not in merged and tr.seen < t]:
            if t - track.seen > o.lost_timeout_s:
                self._tracks.remove(track)
                if track.reported:
                    self._gone.append(_Gone(track.id, track.centre, track.tallest_mm, t))
                    out.append(Tracked(track.id, HandState.LOST, None, _vec(track.centre)))
            elif track.reported:
                out.append(Tracked(track.id, HandState.TRACKING, None, _vec(track.predicted(t, o.match_max_gap_s))))
        return sorted(out, key=lambda u: u.id)

    def _report(self, track: _Track, person: Person) -> Tracked:
        state = HandState.TRACKING if track.reported else HandState.NEW
        track.reported = True
        return Tracked(track.id, state, person, _vec(track.centre))

    # -- matching ----------------------------------------------------------------------------
    def _cost(self, t: float, track: _Track, person: Person) -> float | None:
        """The cost of `person` being `track` (mm), None outside the gate."""
        o = self.options
        predicted = track.predicted(t, o.match_max_gap_s)
        d = person.centre - predicted
        distance = float(np.sqrt(d[0] ** 2 + (0.5 * d[1]) ** 2 + d[2] ** 2))
        overlap = 0.0
        if track.mask is not None and track.mask.shape == person.segment.mask.shape:
            overlap = np.count_nonzero(track.mask & person.segment.mask) / max(1, np.count_nonzero(track.mask))
        gate = o.match_slack_mm + o.max_speed_mm_s * min(t - track.seen, o.match_max_gap_s)
        if distance > gate and overlap < o.same_place_overlap:
            return None
        return distance + o.height_weight * abs(person.top_mm - track.top_mm) - o.overlap_bonus_mm * overlap

    def _match(self, t: float, people: list[Person]) -> dict[_Track, Person]:
        """The assignment of people to live tracks with the smallest total cost."""
        tracks = [tr for tr in self._tracks if t - tr.seen <= self.options.lost_timeout_s]
        if not tracks or not people:
            return {}
        allowed = {}
        for i, tr in enumerate(tracks):
            for j, p in enumerate(people):
                cost = self._cost(t, tr, p)
                if cost is not None:
                    allowed[i, j] = cost
        return {tracks[i]: people[j] for i, j in best_assignment(allowed, len(tracks), len(people))}

    def _owner(self, t: float, piece: Person, matched: dict[_Track, Person]) -> _Track | None:
        """The matched person a further piece belongs to (the far side of someone in front), if any."""
        o = self.options
        near = []
        for track, person in matched.items():
            predicted = track.predicted(t, o.match_max_gap_s)
            dx, dz = abs(piece.centre[0] - predicted[0]), abs(piece.centre[2] - person.centre[2])
            if dx <= o.piece_width_mm and dz <= o.piece_depth_mm:
                near.append((dx, track))
        return min(near, key=lambda n: n[0])[1] if near else None

    # -- lifecycle ---------------------------------------------------------------------------
    def _seen(self, track: _Track, t: float, person: Person) -> None:
        dt = t - track.seen
        if dt > 0:
            measured = (person.centre - track.centre) / dt
            measured[1] = 0.0
            a = self.options.velocity_smoothing
            track.velocity = (1 - a) * track.velocity + a * measured
            speed = float(np.linalg.norm(track.velocity))
            if speed > self.options.max_speed_mm_s:
                track.velocity *= self.options.max_speed_mm_s / speed
        track.centre, track.top_mm, track.seen = person.centre.copy(), person.top_mm, t
        track.tallest_mm = max(track.tallest_mm, person.top_mm)
        track.mask = person.segment.mask

    def _birth(self, t: float, person: Person) -> _Track:
        track = _Track(self._returning(person) or self._free_id(), person.centre.copy(), np.zeros(3),
                       person.top_mm, t, person.segment.mask, tallest_mm=person.top_mm)
        self._tracks.append(track)
        return track

    def _returning(self, person: Person) -> int | None:
        """The id of a person lost recently about here and not taller, if any (the nearest)."""
        o = self.options
        close = [(float(np.hypot(*(person.centre - g.centre)[[0, 2]])), g) for g in self._gone
                 if person.top_mm <= g.tallest_mm + o.return_height_mm]
        close = [(d, g) for d, g in close if d <= o.return_mm]
        if not close:
            return None
        gone = min(close, key=lambda c: c[0])[1]
        self._gone.remove(gone)
        return gone.id

    def _free_id(self) -> int:
        """The smallest id neither in view nor waiting for someone to come back."""
        taken = {tr.id for tr in self._tracks} | {g.id for g in self._gone}
        return next(i for i in range(1, 256) if i not in taken)


def _union(parts: list[Person]) -> Person:
    """One person from the pieces a nearer person cuts them into (the biggest piece's centre)."""
    main = max(parts, key=lambda p: p.cells)
    mask = np.logical_or.reduce([p.segment.mask for p in parts])
    return Person(replace(main.segment, mask=mask), main.centre, max(p.top_mm for p in parts),
                  sum(p.cells for p in parts))


def _vec(a: np.ndarray) -> tuple[float, float, float]:
    return (float(a[0]), float(a[1]), float(a[2]))
