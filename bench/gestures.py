"""Gesture recognition: precision, recall, F1 and latency, on real recordings and synthetic shows.

(a) real: the UTD-MHAD dev recordings (utd-mhad-dev in --data), one performance per clip:
    the recogniser alone on the skeleton's hand trajectories (CSV, as `issv gestures` reads them)
    and the whole backend on the depth clips (as `issv track`). A clip of gesture g counts as a
    true positive if g completes in it; g completing in a clip of another scored action (the
    other gestures and the clearly different actions) is a false positive. False fires: clips of
    the clearly different actions with any gesture. Latency (trajectories, swipes and push): from
    the end of the stroke, read off the skeleton (the first instant after the hand's peak speed
    when its speed is below a quarter of the peak), to COMPLETE.
(b) synthetic: the synthetic performer's default show (every gesture, idles, two walks) over
    varied performers (height, distance, speed, handedness, noise); events are matched to the
    source's truth intervals (Truth.gestures): a COMPLETE of the same gesture between the
    interval's start and 1 s after its end. Latency: COMPLETE minus the interval's end (negative:
    recognised before the motion ended, as a wave is). Both the recogniser alone on the truth
    hands and body, and the whole backend on the rendered depth.
(c) unseen performers, approximated: the real trajectories again with the body and its reach
    scaled about the torso (smaller and taller people), time stretched (faster and slower
    performers) and tracker jitter added; and the real depth clips again with the performer
    re-projected farther from the camera, scaled about the spine (smaller and taller people),
    played faster (frames skipped), with a Kinect's depth noise added on top of their own, and
    cut shorter after the action. Recall and false fires per variation, and the worst person (the
    performer and gesture with the lowest recall: a cliff is often one person's style, UTD-MHAD s3's
    short pushes at 0.85x size). The rules are in millimetres and seconds, so this shows the margin
    they leave, not a tuning target.
(d) every person of the three real datasets (UTD-MHAD, MSRC-12, Kinder-Gator skeletons), scored
    as score.py scores them, per person and worst person, with the thresholds that were chosen
    on data chosen again without each person (leave one person out): bench/people.py, the
    open engine's recogniser (`--backend openiss`) only.
"""
from __future__ import annotations

import glob
import os
import tempfile
from collections import defaultdict
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from bench import people
from bench.common import data_set, parse_args, percentiles, report, tracked
from host import GestureState
from host.commands.gestures import TrajectoryFrame, read_trajectories
from host.plugins import default_registry

DATA = Path("utd-mhad-dev")  # in the --data folder (main() resolves it)
POSITIVE = {"swipe_left": "swipe_left", "swipe_right": "swipe_right", "wave": "wave", "push": "click"}
MIRROR_IMAGE = {"swipe_left": "swipe_right", "swipe_right": "swipe_left"}
NEGATIVE = {"clap", "arm_curl", "jog", "walk", "sit2stand", "stand2sit", "lunge", "squat"}
SECTION = {"recogniser": "synth truth", "backend": "synth depth"}  # the recogniser on truth hands; the backend on depth
MATCH_AFTER_S = 1.0  # a COMPLETE up to this long after a truth interval's end still matches it
PERFORMERS = {  # name -> synthetic source options (default: 1.75 m tall, 2.5 m away, right-handed)
    "default": {},
    "1.55 m, 1.8 m away": {"height_mm": 1550, "distance_mm": 1800},
    "1.95 m, 3.5 m away": {"height_mm": 1950, "distance_mm": 3500},
    "a child, 1.2 m, 2 m away": {"height_mm": 1200, "distance_mm": 2000},
    "left-handed": {"handedness": "left"},
    "slow (x0.75)": {"speed": 0.75},
    "fast (x1.3)": {"speed": 1.3},
    "noisy (x2.5)": {"noise": 2.5, "holes": 2.5},
    "unmirrored": {"mirrored": False},
}


@dataclass
class Tally:
    """Per gesture: true positives, false positives, false negatives, latencies (s)."""

    tp: dict[str, int] = field(default_factory=lambda: defaultdict(int))
    fp: dict[str, int] = field(default_factory=lambda: defaultdict(int))
    fn: dict[str, int] = field(default_factory=lambda: defaultdict(int))
    latency: dict[str, list[float]] = field(default_factory=lambda: defaultdict(list))

    def figures(self) -> dict[str, dict]:
        out = {}
        for g in sorted(set(self.tp) | set(self.fp) | set(self.fn)):
            tp, fp, fn = self.tp[g], self.fp[g], self.fn[g]
            p = tp / (tp + fp) if tp + fp else None
            r = tp / (tp + fn) if tp + fn else None
            f1 = 2 * p * r / (p + r) if p and r else (0.0 if p is not None and r is not None else None)
            lat = self.latency.get(g, [])
            out[g] = {"precision": p, "recall": r, "f1": f1, "tp": tp, "fp": fp, "fn": fn,
                      "latency_s": percentiles(lat, (50, 90)) if lat else None}
        return out


@dataclass(frozen=True)
class Variation:
    """How an unseen performer may differ from the dev pair."""

    scale: float = 1.0  # body and reach, about the torso
    tempo: float = 1.0  # > 1: the same performance, slower
    jitter_mm: float = 0.0  # per coordinate, on the hands

    def apply(self, frame: TrajectoryFrame, rng: np.random.Generator) -> TrajectoryFrame:
        torso = np.array(frame.body.get("torso", (0.0, 0.0, 0.0)))

        def move(p, jitter: float = 0.0) -> tuple[float, float, float]:
            q = torso + self.scale * (np.asarray(p) - torso)
            if jitter:
                q = q + rng.normal(0.0, jitter, 3)
            return (float(q[0]), float(q[1]), float(q[2]))

        return TrajectoryFrame(frame.t * self.tempo,
                               [replace(h, position=move(h.position, self.jitter_mm)) for h in frame.hands],
                               {name: move(p) for name, p in frame.body.items()})


VARIATIONS = {
    "0.8x size": Variation(scale=0.8), "1.25x size": Variation(scale=1.25),
    "faster (0.7x time)": Variation(tempo=0.7), "slower (1.4x time)": Variation(tempo=1.4),
    "jitter 15 mm": Variation(jitter_mm=15.0),
}


@dataclass(frozen=True)
class DepthVariation:
    """How an unseen performer's depth may differ from the dev pair's, made from a real clip."""

    farther_mm: float = 0.0  # every reading re-projected this much farther away (a smaller image)
    aside_mm: float = 0.0  # and this much to the image's right: a performer off the camera's axis
    scale: float = 1.0  # a smaller or taller performer: every reading scaled about the spine joint
    tempo: float = 1.0  # < 1: the same performance in that share of its time, faster (frames skipped at the same rate)
    stretch: float = 1.0  # > 1: the same frames over a longer time (slower, seen at a lower frame rate)
    left_handed: bool = False  # the mirror image: the other arm does it, swipes go the other way
    kinect_noise: float = 0.0  # extra depth noise, in units of a Kinect v1's (sigma = 1.425e-6 z^2 mm)
    holes: float = 0.0  # share of readings dropped
    ends_sooner_s: float = 0.0  # the recording stops this much earlier after the action

    def label(self, label: str) -> str:
        """The action as this performer performs it (a mirror image swipes the other way)."""
        return MIRROR_IMAGE.get(label, label) if self.left_handed else label

    def apply(self, clip, rng: np.random.Generator) -> dict[str, np.ndarray]:
        """The clip's arrays (the depth clip format of docs/architecture.md) as this performer would give them."""
        kept = len(clip) - int(round(self.ends_sooner_s * clip.fps))
        index = np.clip(np.round(np.arange(0, kept, 1 / self.tempo)).astype(int), 0, kept - 1)
        k = clip.intrinsics
        spines = clip.body[:, 1] if clip.body is not None else np.zeros((len(clip), 3))
        depth = np.stack([self._frame(clip.depth[i], k, spines[i], rng) for i in index])
        out = {"depth": depth, "timestamps": np.arange(len(index)) * self.stretch / clip.fps,
               "mirrored": clip.mirrored, "intrinsics": np.array([k.fx, k.fy, k.cx, k.cy]),
               "label": self.label(clip.label)}
        if clip.hands is not None and clip.body is not None:
            hands, body = (self._move(points[index], spines[index, None], k, depth.shape[2])
                           for points in (clip.hands, clip.body))
            if self.left_handed:  # the performer's sides trade places: [left, right]; head, spine, shoulders
                hands, body = hands[:, ::-1], body[:, [0, 1, 3, 2]]
            out |= {"hands": hands, "body": body}
        return out

    def _move(self, points: np.ndarray, spine: np.ndarray, k, width: int) -> np.ndarray:
        moved = spine + self.scale * (points - spine) + np.array([self.aside_mm, 0.0, self.farther_mm])
        if self.left_handed:  # the image flipped left to right: column u goes to width - 1 - u
            moved[..., 0] = (width - 1 - 2 * k.cx) * moved[..., 2] / k.fx - moved[..., 0]
        return moved

    def _frame(self, depth: np.ndarray, k, spine: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """The frame's readings moved in the world and drawn again, nearer ones last (on top)."""
        v, u = np.nonzero(depth)
        z = depth[v, u].astype(np.float64)
        magnified = self.scale * float(np.median(z) / (np.median(z) + self.farther_mm)) if z.size else 1.0
        if self.farther_mm or self.aside_mm or self.scale != 1.0 or self.left_handed:
            points = np.stack([(u - k.cx) * z / k.fx, (k.cy - v) * z / k.fy, z], axis=1)
            moved = self._move(points, spine, k, depth.shape[1])
            z = moved[:, 2]
            u = np.round(k.cx + moved[:, 0] * k.fx / z).astype(int)
            v = np.round(k.cy - moved[:, 1] * k.fy / z).astype(int)
            inside = (u >= 0) & (u < depth.shape[1]) & (v >= 0) & (v < depth.shape[0])
            u, v, z = u[inside], v[inside], z[inside]
        if self.kinect_noise:
            z = z + rng.normal(0.0, 1.0, z.size) * self.kinect_noise * 1.425e-6 * z ** 2
        keep = rng.random(z.size) >= self.holes
        order = np.argsort(-z[keep])
        u, v, z = u[keep][order], v[keep][order], np.clip(z[keep][order], 1, 65535).astype(np.uint16)
        out = np.zeros_like(depth)
        spread = int(np.ceil(magnified))  # a larger image: each reading covers more than one pixel
        for du in range(spread):
            for dv in range(spread):
                out[np.minimum(v + dv, depth.shape[0] - 1), np.minimum(u + du, depth.shape[1] - 1)] = z
        return out


DEPTH_VARIATIONS = {
    "0.7 m farther": DepthVariation(farther_mm=700), "1.4 m farther": DepthVariation(farther_mm=1400),
    "0.85x size": DepthVariation(scale=0.85), "1.15x size": DepthVariation(scale=1.15),
    "0.5 m off the camera's axis": DepthVariation(aside_mm=500),
    "faster (0.7x time)": DepthVariation(tempo=0.7),
    "slower (1.4x time, 21 fps)": DepthVariation(stretch=1.4),
    "left-handed (mirror image)": DepthVariation(left_handed=True),
    "Kinect noise x2, 3 % holes": DepthVariation(kinect_noise=2, holes=0.03),
    "recording stops 0.4 s sooner": DepthVariation(ends_sooner_s=0.4),
}


def recognizer(backend: str):
    return default_registry().get("backends", backend).cls.recognizer(None)


def label_of(path: str) -> str:
    return os.path.splitext(os.path.basename(path))[0].split("_", 3)[-1]


def stroke_end(times: np.ndarray, positions: np.ndarray) -> float:
    """End of a hand's main stroke: first instant after its peak speed with speed < peak / 4."""
    speed = np.linalg.norm(np.diff(positions, axis=0), axis=1) / np.diff(times)
    peak = int(np.argmax(speed))
    after = np.nonzero(speed[peak:] < speed[peak] / 4)[0]
    return float(times[peak + after[0] + 1]) if after.size else float(times[-1])


def clip_tally(completed: dict[str, set[str]], labels: dict[str, str]) -> tuple[Tally, float, dict]:
    """Clip-level tally over the scored clips, the false-fire rate on the negatives, fires elsewhere."""
    tally, fires, negatives, elsewhere = Tally(), 0, 0, defaultdict(int)
    for path, names in completed.items():
        label = labels[path]
        want = POSITIVE.get(label)
        if label in POSITIVE or label in NEGATIVE:
            for g in POSITIVE.values():
                if g == want:
                    tally.tp[g] += g in names
                    tally.fn[g] += g not in names
                elif g in names:
                    tally.fp[g] += 1
            for g in names - set(POSITIVE.values()):
                tally.fp[g] += 1
            if label in NEGATIVE:
                negatives += 1
                fires += bool(names)
        else:
            for g in names:
                elsewhere[f"{label}:{g}"] += 1
    return tally, (fires / negatives if negatives else float("nan")), dict(elsewhere)


def worst_person(completed: dict[str, set[str]], labels: dict[str, str]) -> dict | None:
    """The performer and gesture with the lowest recall over that performer's clips of it (UTD-MHAD
    names its subjects s1, s2, ...): where a variation finds a cliff, it is often one person's."""
    hits: dict[tuple[str, str], list[bool]] = defaultdict(list)
    for path, names in completed.items():
        want = POSITIVE.get(labels[path])
        if want is not None:
            hits[people.person_of(os.path.basename(path)), want].append(want in names)
    if not hits:
        return None
    (person, gesture), got = min(hits.items(), key=lambda item: np.mean(item[1]))
    return {"person": person, "gesture": gesture, "recall": float(np.mean(got))}


def real_trajectories(backend: str, variation: Variation = Variation(), what: str = "real trajectories") -> dict:
    files = sorted(glob.glob(str(DATA / "trajectories" / "*.csv")))
    completed, labels, tally_latency = {}, {}, defaultdict(list)
    rng = np.random.default_rng(0)
    for path in tracked(files, what):
        labels[path] = label_of(path)
        completed[path], latency = _trajectory(backend, Path(path), POSITIVE.get(labels[path]), variation, rng)
        if latency is not None:
            tally_latency[POSITIVE[labels[path]]].append(latency)
    tally, fire_rate, elsewhere = clip_tally(completed, labels)
    tally.latency = tally_latency
    return {"gestures": tally.figures(), "false_fire_rate": fire_rate, "fires_on_other_actions": elsewhere,
            "worst_person": worst_person(completed, labels), "clips": len(files)}


def _trajectory(backend: str, path: Path, want: str | None, variation: Variation, rng) -> tuple[set[str], float | None]:
    """One trajectory file through the recogniser: the gestures it completed, and how long after
    its stroke ended the swipe or push `want` completed (None: not completed, or a wave)."""
    rec, names, times, hands = recognizer(backend), set(), [], defaultdict(list)
    first_complete: dict[str, float] = {}
    for frame in read_trajectories(path):
        frame = variation.apply(frame, rng)
        for g in rec.update(frame.t, frame.hands, frame.body, True):
            if g.state is GestureState.COMPLETE:
                names.add(g.name)
                first_complete.setdefault(g.name, g.timestamp)
        times.append(frame.t)
        for h in frame.hands:
            hands[h.side.value].append(h.position)
    for g in rec.finish():  # the file ended: as `issv gestures` does
        names.add(g.name)
        first_complete.setdefault(g.name, g.timestamp)
    if want not in first_complete or want == "wave":  # a wave has no single stroke to end
        return names, None
    tracks = [np.array(p) for p in hands.values() if len(p) == len(times)]
    t = np.array(times)
    fastest = max(tracks, key=lambda p: float(np.max(np.linalg.norm(np.diff(p, axis=0), axis=1) / np.diff(t))))
    return names, first_complete[want] - stroke_end(t, fastest)


def real_clips(backend: str, limit: int | None, variation: DepthVariation | None = None,
               what: str = "real depth clips") -> dict:
    from sources.clip import Clip, ClipOptions, ClipSource

    files = [f for f in sorted(glob.glob(str(DATA / "clips" / "*.npz")))
             if label_of(f) in POSITIVE or label_of(f) in NEGATIVE][:limit]
    cls = default_registry().get("backends", backend).cls
    completed, labels = {}, {}
    rng = np.random.default_rng(0)
    with tempfile.TemporaryDirectory() as scratch:
        for path in tracked(files, what):
            labels[path] = variation.label(label_of(path)) if variation is not None else label_of(path)
            played = path
            if variation is not None:  # a real file, as an unseen clip would be
                played = os.path.join(scratch, "varied.npz")
                np.savez(played, **variation.apply(Clip(path), rng))
            names = set()
            with cls(ClipSource(ClipOptions(path=played))) as b:
                while (frame := b.update()) is not None:
                    names |= {g.name for g in frame.gestures if g.state is GestureState.COMPLETE}
                names |= {g.name for g in b.finish() if g.state is GestureState.COMPLETE}
            completed[path] = names
    tally, fire_rate, _ = clip_tally(completed, labels)
    return {"gestures": tally.figures(), "false_fire_rate": fire_rate, "worst_person": worst_person(completed, labels),
            "clips": len(files)}


def match(events: list[tuple[float, str]], truth: list, tally: Tally) -> None:
    """Pair COMPLETE events with truth intervals of the same gesture; the rest are errors."""
    unmatched = list(events)
    for g in sorted(truth, key=lambda g: g.end):
        hit = next(((t, n) for t, n in unmatched if n == g.name and g.start <= t <= g.end + MATCH_AFTER_S), None)
        if hit is None:
            tally.fn[g.name] += 1
        else:
            unmatched.remove(hit)
            tally.tp[g.name] += 1
            tally.latency[g.name].append(hit[0] - g.end)
    for _, name in unmatched:
        tally.fp[name] += 1


def show(cls, options, with_tracker: bool):
    """(depth frame, the backend's gestures) per frame of a synthetic show; no gestures without tracker."""
    from sources.synthetic import SyntheticSource

    source = SyntheticSource(options)
    if with_tracker:
        with cls(source) as backend:
            while (frame := backend.update()) is not None:
                yield frame.depth, frame.gestures
        return
    source.open()
    try:
        while (depth := source.read()) is not None:
            yield depth, ()
    finally:
        source.close()


def synthetic(backend: str, performers: dict[str, dict], with_tracker: bool) -> dict:
    """Per performer and overall: the recogniser on truth hands, and (with_tracker) the whole backend."""
    from sources.synthetic import SyntheticOptions

    cls = default_registry().get("backends", backend).cls
    kinds = ("recogniser", "backend") if with_tracker else ("recogniser",)
    overall = {kind: Tally() for kind in kinds}
    per = {}
    for label, options in performers.items():
        rec, truth = recognizer(backend), {}
        events: dict[str, list[tuple[float, str]]] = {kind: [] for kind in kinds}
        for depth, gestures in show(cls, SyntheticOptions(seed=1, width=320, height=240, **options), with_tracker):
            body = {k: v for k, v in depth.truth.body.items() if k in ("torso", "head")}
            on_truth = rec.update(depth.timestamp, _truth_hands(depth), body, depth.mirrored)
            for kind, found in (("recogniser", on_truth), ("backend", gestures)):
                if kind in events:
                    events[kind] += [(g.timestamp, g.name) for g in found if g.state is GestureState.COMPLETE]
            for g in depth.truth.gestures:
                truth[(g.name, g.start)] = g
        per[label] = {}
        for kind in kinds:
            tally = Tally()
            match(events[kind], list(truth.values()), tally)
            match(events[kind], list(truth.values()), overall[kind])
            per[label][kind] = tally.figures()
    return {"performers": per, "overall": {kind: t.figures() for kind, t in overall.items()}}


def _truth_hands(depth):
    from host import Hand, HandState

    ids = {"left": 1, "right": 2}
    return [Hand(ids[side.value], HandState.TRACKING, pos, side) for side, pos in depth.truth.hands.items()]


def _fmt(v) -> str:
    return "-" if v is None else f"{v:.2f}"


def rows_of(section: str, gestures: dict) -> list[list]:
    rows = []
    for g, f in gestures.items():
        lat = f["latency_s"]
        rows.append([section, g, _fmt(f["precision"]), _fmt(f["recall"]), _fmt(f["f1"]),
                     f"{f['tp']}/{f['fp']}/{f['fn']}",
                     "-" if lat is None else f"{lat['p50']:+.2f}/{lat['p90']:+.2f}"])
    return rows


def _worst(fig: dict) -> str:
    w = fig.get("worst_person")
    if not w:
        return ""
    return f"worst {w['person']} {w['gesture']} {_fmt(w['recall'])}" if w["recall"] < 1 else "every person 1.00"


def _table(figures: dict) -> list[list]:
    """The rows of the printed table: real, synthetic per performer, then each variation."""
    rows = rows_of("real csv", figures["real_trajectories"]["gestures"])
    rows.append(["real csv", "false fires", _fmt(figures["real_trajectories"]["false_fire_rate"]),
                 "", _worst(figures["real_trajectories"]), "", ""])
    if "real_clips" in figures:
        rows += rows_of("real depth", figures["real_clips"]["gestures"])
        rows.append(["real depth", "false fires", _fmt(figures["real_clips"]["false_fire_rate"]), "",
                     _worst(figures["real_clips"]), "", ""])
    for kind, gestures in figures["synthetic"]["overall"].items():
        rows += rows_of(SECTION[kind], gestures)
    for performer, kinds in figures["synthetic"]["performers"].items():
        for kind, gestures in kinds.items():
            tp, fp, fn = (sum(f[k] for f in gestures.values()) for k in ("tp", "fp", "fn"))
            rows.append([SECTION[kind], performer, "", _fmt(tp / (tp + fn) if tp + fn else None), "",
                         f"{tp}/{fp}/{fn}", ""])
    for kind, section in (("csv", "varied_trajectories"), ("depth", "varied_clips")):
        for name, fig in figures.get(section, {}).items():
            tp, fp, fn = (sum(f[k] for f in fig["gestures"].values()) for k in ("tp", "fp", "fn"))
            recalls = " ".join(f"{g} {_fmt(f['recall'])}" for g, f in fig["gestures"].items()
                               if f["recall"] is not None)
            worst = _worst(fig)
            rows.append([f"{kind} {name}", f"false fires {_fmt(fig['false_fire_rate'])}", "",
                         _fmt(tp / (tp + fn) if tp + fn else None), f"{recalls}; {worst}" if worst else recalls,
                         f"{tp}/{fp}/{fn}", ""])
    return rows


def main() -> None:
    def extra(p):
        p.add_argument("--backend", default="openiss")
        p.add_argument("--quick", action="store_true", help="recogniser only: no depth tracking (faster)")
        p.add_argument("--clips", type=int, default=None, help="at most this many real depth clips")

    global DATA
    args = parse_args(__doc__.splitlines()[0], extra, data=True)
    DATA = data_set(args, "utd-mhad-dev", "(a) and (c), every real UTD-MHAD row")
    if DATA is None:
        figures = {"backend": args.backend, "synthetic": synthetic(args.backend, PERFORMERS, not args.quick)}
        rows = [r for kind, gestures in figures["synthetic"]["overall"].items() for r in rows_of(SECTION[kind], gestures)]
        report(f"gestures, backend {args.backend} (synthetic only)", figures, rows,
               ["data", "gesture", "precision", "recall", "F1", "tp/fp/fn", "latency p50/p90"], args.json)
        return
    figures = {"backend": args.backend, "real_trajectories": real_trajectories(args.backend)}
    if not args.quick:
        figures["real_clips"] = real_clips(args.backend, args.clips)
    figures["synthetic"] = synthetic(args.backend, PERFORMERS, with_tracker=not args.quick)
    figures["varied_trajectories"] = {name: real_trajectories(args.backend, v, f"trajectories as {name}")
                                      for name, v in VARIATIONS.items()}
    if not args.quick:
        figures["varied_clips"] = {name: real_clips(args.backend, args.clips, v, f"depth clips as {name}")
                                   for name, v in DEPTH_VARIATIONS.items()}
    rows = _table(figures)
    if args.backend == "openiss" and data_set(args, "msrc12-dev", "(d), the people of all three datasets"):
        figures["people"] = people.measure(args.data)
    report(f"gestures, backend {args.backend} (latency: COMPLETE - end of motion, s)", figures, rows,
           ["data", "gesture", "precision", "recall", "F1", "tp/fp/fn", "latency p50/p90"], args.json)
    if "people" in figures and not args.json:
        people.print_tables(figures["people"])


if __name__ == "__main__":
    main()
