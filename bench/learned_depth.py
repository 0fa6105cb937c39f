"""Learned gestures through depth: UTD-MHAD clips tracked by the open engine (ISSV_DATA/utd-mhad-dev).

Reference (`reference`): what a learned gesture is measured against. Every clip's hands, as the
open engine tracks them, become postures (host/learned/features.py) measured against the engine's
own torso and head (what teaching and the show use where a backend reports users), and against the
torso estimated from the hands (a backend reporting hands only). Each is compared with the postures
of the clip's Kinect skeleton (hands, spine, head; two frames earlier, as score.py compares hands:
the skeleton runs about 1.75 frames ahead of its depth): the mean distance of the two hands, in body
units (head-torso distances), overall and per action.

Teaching (`taught`): six actions outside the dictionary (draw_x, draw_circle_cw, draw_triangle,
bowling, tennis_serve, baseball_swing) learned from subjects 1 and 2's clips (`issv learn` on depth
clips: one repetition each), then every clip of subjects 3 and 4 through `issv track --learned`
with all six. Recall: a COMPLETE of the clip's action; a false fire: a clip in which a learned
gesture other than its own completes. Single 2-second clips by two people are the hardest way to
teach (docs/learned-gestures.md asks for several repetitions per take): these figures show what
depth does to learned gestures, not what they can do.
"""
from __future__ import annotations

import collections
import io
import json
import tempfile
from pathlib import Path

import numpy as np

from bench.common import data_set, parse_args, report, tracked
from bench.gestures import label_of
from bench.people import person_of
from host.app import plugin_class
from host.commands.track import track
from host.learned.examples import read_take
from host.learned.features import PostureStream, performer_body
from host.learned.learner import learn
from host.model import Hand, HandState, Side

ACTIONS = ("draw_x", "draw_circle_cw", "draw_triangle", "bowling", "tennis_serve", "baseball_swing")
TEACHERS, CHECKED = ("s1", "s2"), ("s3", "s4")
SKELETON_LEAD = 2  # frames: the skeleton of frame i - 2 goes with the depth of frame i (score.py)


def _clip_parts(clip: Path) -> tuple[str, str]:
    """a12_s1_t1_bowling.npz -> ("s1", "bowling"), as bench.people and bench.gestures read the names."""
    return person_of(clip.name), label_of(str(clip))


def _clip_and_engine() -> tuple[type, type]:
    """The clip source and the open engine, as a profile would name them."""
    return plugin_class("sources", "clip"), plugin_class("backends", "openiss")


def _skeleton_hands(hands: np.ndarray) -> list[Hand]:
    if not np.all(np.isfinite(hands)):
        return []
    return [Hand(i + 1, HandState.TRACKING, tuple(hands[i]), side) for i, side in enumerate((Side.LEFT, Side.RIGHT))]


def _errors(clip: Path) -> dict[str, list[float]]:
    """One clip: per posture, the distance (body units, mean of the hands) of the engine's postures
    measured against its body and against the estimate, from the skeleton's."""
    data = np.load(clip)
    source_cls, backend_cls = _clip_and_engine()
    streams = {"body": PostureStream(True), "estimate": PostureStream(True)}
    truth = PostureStream(True)
    out: dict[str, list[float]] = {"body": [], "estimate": []}
    with backend_cls(source_cls(source_cls.Options(path=str(clip))), backend_cls.Options()) as tracker:
        i = 0
        while (frame := tracker.update()) is not None:
            if frame.depth is None:
                continue
            j, i = max(0, i - SKELETON_LEAD), i + 1
            t = frame.timestamp
            got = {"body": streams["body"].update(t, frame.hands, performer_body(frame)),
                   "estimate": streams["estimate"].update(t, frame.hands, {})}
            want = truth.update(t, _skeleton_hands(data["hands"][j]),
                                {"head": tuple(data["body"][j, 0]), "torso": tuple(data["body"][j, 1])})
            for kind, postures in got.items():
                if len(postures) == len(want):
                    out[kind] += [float(np.linalg.norm((p.vector - q.vector).reshape(2, 3), axis=1).mean())
                                  for p, q in zip(postures, want)]
    return out


def reference(clips: list[Path]) -> dict:
    overall: dict[str, list[float]] = collections.defaultdict(list)
    per_action: dict[str, dict[str, list[float]]] = collections.defaultdict(lambda: collections.defaultdict(list))
    for clip in tracked(clips, "postures against the skeleton"):
        for kind, errors in _errors(clip).items():
            overall[kind] += errors
            per_action[_clip_parts(clip)[1]][kind] += errors
    return {"clips": len(clips),
            "overall": {k: {"median": float(np.median(v)), "p90": float(np.percentile(v, 90)), "postures": len(v)}
                        for k, v in overall.items()},
            "per_action_median": {a: {k: float(np.median(v)) for k, v in kinds.items()}
                                  for a, kinds in sorted(per_action.items())}}


def taught(clips: list[Path], folder: Path) -> dict:
    files, learned = [], {}
    for name in ACTIONS:
        takes = [read_take(str(c), True) for c in clips if _clip_parts(c) in {(t, name) for t in TEACHERS}]
        gesture = learn(name, takes)
        gesture.save(folder / f"{name}.gesture.json")
        files.append(folder / f"{name}.gesture.json")
        learned[name] = {"threshold": gesture.threshold, "hands": gesture.hands}
    source_cls, backend_cls = _clip_and_engine()
    hits: dict[str, dict[str, list[int]]] = collections.defaultdict(lambda: collections.defaultdict(lambda: [0, 0]))
    fired, with_wrong = collections.Counter(), [0, 0]  # clips with another learned gesture, clips
    for clip in tracked([c for c in clips if _clip_parts(c)[0] in CHECKED], "learned gestures on s3-s4"):
        subject, label = _clip_parts(clip)
        out = io.StringIO()
        track(clip, backend_cls, source_cls, None, out, files)
        names = {e["name"] for e in map(json.loads, out.getvalue().splitlines())
                 if e.get("native") == "learned" and e.get("state") == "complete"}
        if label in ACTIONS:
            hits[label][subject][0] += label in names
            hits[label][subject][1] += 1
        wrong = names - {label}
        with_wrong[0] += bool(wrong)
        with_wrong[1] += 1
        fired.update(wrong)
    recall = {a: sum(h for h, _ in s.values()) / sum(n for _, n in s.values()) for a, s in hits.items()}
    return {"learned": learned, "recall": recall, "mean_recall": float(np.mean(list(recall.values()))),
            "by_person": {a: {s: h / n for s, (h, n) in sorted(per.items())} for a, per in hits.items()},
            "false_fire_rate": with_wrong[0] / with_wrong[1], "clips": with_wrong[1],
            "false_fires_by_gesture": dict(fired)}


def main() -> None:
    args = parse_args(__doc__.splitlines()[0], data=True)
    utd = data_set(args, "utd-mhad-dev", "learned gestures through depth")
    if utd is None:
        return
    clips = sorted((utd / "clips").glob("*.npz"))
    ref = reference(clips)
    with tempfile.TemporaryDirectory() as tmp:
        teach = taught(clips, Path(tmp))
    rows = [["reference", f"postures vs the skeleton, against the {kind} ({v['postures']} postures)", v["median"],
             f"p90 {v['p90']:.3f}"] for kind, v in ref["overall"].items()]
    rows += [["reference", f"  {action}", v["body"], f"estimate {v['estimate']:.3f}"]
             for action, v in ref["per_action_median"].items()]
    for action, recall in teach["recall"].items():
        learned = teach["learned"][action]
        rows.append(["taught s1-s2", f"{action} ({learned['hands']}, threshold {learned['threshold']:.2f})", recall,
                     " ".join(f"{s} {v:.2f}" for s, v in teach["by_person"][action].items())])
    rows.append(["taught s1-s2", f"mean recall / clips with another learned gesture ({teach['clips']})",
                 teach["mean_recall"], f"{teach['false_fire_rate']:.3f} {teach['false_fires_by_gesture']}"])
    report("Learned gestures through depth (UTD-MHAD, the open engine)", {"reference": ref, "taught": teach},
           rows, ["part", "what", "median / recall", "more"], args.json)


if __name__ == "__main__":
    main()
