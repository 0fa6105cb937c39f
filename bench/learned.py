"""Learned gestures on MSRC-12 (issue 18's protocol), teachers p01-p03, checked on p04-p10.

For each of goggles (G4), wind_it_up (G5), shoot (G6), throw (G8), change_weapon (G10) and
beat_both (G11): `issv learn` on the whole recordings of that gesture by p01, p02 and p03 (the
learner cuts the repetitions itself), then `issv gestures STREAM --mirrored --learned ...` with
all six files on every recording of p04-p10. A hit: a COMPLETE event with the right name between
1.5 s before and 1.0 s after an action point. A false fire: an instance of another gesture (the
six, plus crouch, bow, had_enough, kick, lift_outstretched_arms, push_right) in whose window a
learned gesture other than its own completes.

Also, teacher side (how the design parameters were chosen): leave one teacher out, learn from the
other two, score the third the same way (in process, the same functions). And p04-p10 in halves,
p04-p07 and p08-p10: a choice the teachers cannot show (a style only other people perform too) is
made on one half and checked on the other (learner.own_paces).
Hands only (`hands_only`): the protocol with the torso and head rows left out, teaching and
checking alike, as a backend that reports hands alone gives them (the torso is then estimated).
Thresholds (`loosened`): every gesture's threshold scaled as a profile may override it, and the
worst-found gesture's alone: how much loosening finds, and what it costs in false fires.
Teach more: a performer the teachers' gesture misses teaches their own style on top of the
teachers' file, from the first half of their recording; recall on the rest, before and after
(`teach_more`). Other people doing other things (`everyday`): the six on Kinder-Gator's adults
and children walking, running, jumping (nothing may fire) and performing the built-in dictionary;
and what counter-examples (`issv learn --unlike`) do to the confusion found there (`counter_examples`).
And cost: per-frame time of recognising 10 learned gestures (the six and four
more taught from the same takes under other names), CPU time on one core, the time `issv
learn` takes, and the CPU time training the six's classifier takes (`Classifier.train` itself: a
show pays it once per set of files, host/learned/cache.py).

Needs ISSV_DATA (the folder holding msrc12-dev); without it says so and exits.
"""
from __future__ import annotations

import collections
import dataclasses
import json
import os
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

from bench.common import parse_args, report, tracked
from host.commands.gestures import read_trajectories
from host.learned.classifier import Classifier
from host.learned.examples import read_take
from host.learned.gesture_file import load
from host.learned.features import postures
from host.learned.learner import Take, counter_example, learn, taught_before
from host.learned.matcher import taught_repetitions
from host.learned.recognizer import LearnedRecognizer

SIX = {"G4": "goggles", "G5": "wind_it_up", "G6": "shoot", "G8": "throw", "G10": "change_weapon",
       "G11": "beat_both"}
TEACHERS = ("p01", "p02", "p03")
CHECKED = ("p04", "p05", "p06", "p07", "p08", "p09", "p10")
HALVES = {"p04-p07": ("p04", "p05", "p06", "p07"), "p08-p10": ("p08", "p09", "p10")}  # choose on one, check on the other
BEFORE_S, AFTER_S = 1.5, 1.0


def _data() -> Path:
    root = os.environ.get("ISSV_DATA")
    folder = Path(root or "", "msrc12-dev")
    if not root or not folder.is_dir():
        sys.exit("bench.learned needs the MSRC-12 dev streams: set ISSV_DATA to the folder holding msrc12-dev")
    return folder


def streams(folder: Path, persons) -> list[tuple[Path, dict]]:
    out = []
    for csv in sorted(folder.glob("p*_g*.csv")):
        truth = json.loads((folder / "truth" / (csv.stem + ".json")).read_text())
        if truth["person"] in persons:
            out.append((csv, truth))
    return out


def score(runs: list[tuple[dict, list[tuple[float, str]]]]) -> dict:
    """runs: (truth, [(t, name) of COMPLETE learned events]) -> recall per gesture and person, false fires."""
    hits = {g: collections.defaultdict(lambda: [0, 0]) for g in SIX.values()}
    neg = [0, 0]
    neg_by = collections.Counter()
    delays = collections.defaultdict(list)
    for truth, events in runs:
        own = SIX.get(truth["gesture"])
        for tau in truth["tags_s"]:
            window = [(t, n) for t, n in events if tau - BEFORE_S <= t <= tau + AFTER_S]
            if own is not None:
                found = [t for t, n in window if n == own]
                hits[own][truth["person"]][1] += 1
                hits[own][truth["person"]][0] += bool(found)
                if found:
                    delays[own].append(min(found) - tau)
            others = {n for _, n in window if n != own}
            neg[1] += 1
            neg[0] += bool(others)
            neg_by.update(others)
    recall = {g: sum(v[0] for v in ps.values()) / max(1, sum(v[1] for v in ps.values())) for g, ps in hits.items()}
    persons = collections.defaultdict(lambda: [0, 0])
    for ps in hits.values():
        for p, v in ps.items():
            persons[p][0] += v[0]
            persons[p][1] += v[1]
    by_person = {p: v[0] / v[1] for p, v in sorted(persons.items())}
    return {"recall": recall, "mean_recall": float(np.mean(list(recall.values()))),
            "worst_gesture_recall": min(recall.values()),
            "by_person": by_person, "worst_person_recall": min(by_person.values()),
            "by_gesture_person": {g: {p: round(v[0] / v[1], 3) for p, v in sorted(ps.items())}
                                  for g, ps in hits.items()},
            "false_fire_rate": neg[0] / max(1, neg[1]), "false_fires_by_gesture": dict(neg_by),
            "windows": neg[1],
            "delay_s_p50": {g: float(np.median(v)) for g, v in delays.items() if v}}


def by_halves(runs: list[tuple[dict, list[tuple[float, str]]]]) -> dict:
    """`score` of p04-p07 and of p08-p10 apart (HALVES)."""
    return {half: score([(t, e) for t, e in runs if t["person"] in persons]) for half, persons in HALVES.items()}


def _issv(*args: str) -> str:
    r = subprocess.run([sys.executable, "-m", "host", *args], capture_output=True, text=True, timeout=1200)
    if r.returncode != 0:
        sys.exit(f"issv {' '.join(args[:2])} failed: {r.stderr.strip()}")
    return r.stdout


def _learned(stdout: str) -> list[tuple[float, str, str]]:
    """(t, name, state) of every learned-gesture event line."""
    lines = (json.loads(line) for line in stdout.splitlines())
    return [(float(e["t"]), e["name"], e["state"]) for e in lines if e.get("native") == "learned"]


def _completes(events: list[tuple[float, str, str]]) -> list[tuple[float, str]]:
    return [(t, name) for t, name, state in events if state == "complete"]


def announced(runs: list[list[tuple[float, str, str]]]) -> dict:
    """How many COMPLETEs an IN_PROGRESS of the same gesture announced (since its last COMPLETE), how
    early, and the share of announced attempts (IN_PROGRESS) that completed."""
    leads, total, attempts = [], 0, 0
    for events in runs:
        since: dict[str, float] = {}
        for t, name, state in events:
            if state == "in_progress":
                attempts += 1
                since[name] = t  # the latest: an attempt that faded was announced before
            else:
                total += 1
                if name in since:
                    leads.append(t - since.pop(name))
    return {"completes": total, "announced_share": len(leads) / max(1, total),
            "lead_s_p50": float(np.median(leads)) if leads else None,
            "attempts": attempts, "attempts_completed": len(leads) / max(1, attempts)}


def protocol(folder: Path, workdir: Path, jobs: int = 2) -> tuple[dict, list[Path], float, dict]:
    """The judged protocol through the real commands; also the slowest `issv learn` (s) and each
    checked recording's COMPLETE events."""
    files, learn_s = [], []
    for g, name in SIX.items():
        takes = [str(c) for c, t in streams(folder, TEACHERS) if t["gesture"] == g]
        out = workdir / f"{name}.gesture.json"
        start = time.perf_counter()
        _issv("learn", name, *takes, "--mirrored", "-o", str(out))
        learn_s.append(time.perf_counter() - start)
        files.append(out)
    learned = [a for f in files for a in ("--learned", str(f))]
    checked = streams(folder, CHECKED)
    with ThreadPoolExecutor(jobs) as pool:
        outs = list(tracked(pool.map(lambda s: _issv("gestures", str(s[0]), "--mirrored", *learned), checked),
                            "issv gestures on p04-p10", len(checked)))
    events = [_learned(o) for o in outs]
    completed = {c: _completes(e) for (c, _), e in zip(checked, events)}
    out = score([(t, completed[c]) for c, t in checked])
    out["halves"] = by_halves([(t, completed[c]) for c, t in checked])
    out["in_progress"] = announced(events)
    return out, files, max(learn_s), completed


def recognise(recognizer: LearnedRecognizer, csv: Path, body: bool = True) -> tuple[list[tuple[float, str, str]], float]:
    """(t, name, state) of every event on a recording, and its length in seconds; body=False: its
    torso and head rows left out."""
    events, times = [], []
    for frame in read_trajectories(csv):
        times.append(frame.t)
        events += [(e.timestamp, e.name, e.state.value)
                   for e in recognizer.update(frame.t, frame.hands, frame.body if body else {})]
    return events, (times[-1] - times[0] if times else 0.0)


def recognised(gestures: list, checked: list[tuple[Path, dict]], what: str,
               thresholds: dict[str, float] | None = None, body: bool = True) -> list[tuple[dict, list[tuple[float, str]]]]:
    """(truth, COMPLETE events) of each recording, in process (every recogniser of the set shares
    one classifier, trained once), with a progress bar saying `what` runs; `thresholds`: a
    profile's overrides by gesture name; body=False: hands only."""
    return [(t, _completes(recognise(LearnedRecognizer(gestures, True, thresholds), c, body)[0]))
            for c, t in tracked(checked, what)]


def hands_only(folder: Path) -> dict:
    """The protocol with every torso and head row left out, teaching and checking alike, as a backend
    reporting hands only gives them: the torso is estimated from where the hands rest
    (host/learned/features.py). In process; p04-p10 and its halves."""
    def take(csv: Path) -> Take:
        return Take(str(csv), *postures(((f.t, f.hands, {}) for f in read_trajectories(csv)), True))

    gestures = [learn(name, [take(c) for c, t in streams(folder, TEACHERS) if t["gesture"] == g])
                for g, name in SIX.items()]
    runs = recognised(gestures, streams(folder, CHECKED), "hands only, p04-p10", body=False)
    out = score(runs)
    out["halves"] = by_halves(runs)
    return out


SCALES = (0.85, 1.15, 1.3, 2.0)  # thresholds as a share of the taught ones, as a profile may set them


def loosened(files: list[Path], folder: Path, checked: dict) -> dict:
    """The profile's per-gesture `threshold` as the remedy for a missed gesture: every gesture's
    threshold scaled, then the worst-found gesture's alone, by each of SCALES; p04-p10's mean
    recall, that gesture's recall and the false fires at each (1: the protocol's own figures). A
    miss just beyond the threshold comes back when it is loosened; a style the teachers never
    showed does not (docs/learned-gestures.md, "Teaching more")."""
    gestures = [load(f) for f in files]
    worst = min(checked["recall"], key=checked["recall"].get)
    recordings = streams(folder, CHECKED)

    def point(s: dict) -> dict:
        return {"mean_recall": s["mean_recall"], "recall": s["recall"][worst], "false_fire_rate": s["false_fire_rate"]}

    out = {"gesture": worst, "all": {1.0: point(checked)}, "alone": {1.0: point(checked)}}
    for scale in SCALES:
        for which, names in (("all", [g.name for g in gestures]), ("alone", [worst])):
            if which == "alone" and scale < 1.0:
                continue  # tightening one gesture cannot find it more often
            thresholds = {g.name: (scale if g.name in names else 1.0) * g.threshold for g in gestures}
            runs = recognised(gestures, recordings, f"thresholds x{scale} ({which})", thresholds)
            out[which][scale] = point(score(runs))
    return out


def teacher_side(folder: Path) -> dict:
    """Leave one teacher out: learn from the other two, score the third (all 12 gestures' streams)."""
    runs, per_teacher = [], {}
    for held in TEACHERS:
        others = [p for p in TEACHERS if p != held]
        gestures = [learn(name, [read_take(str(c), True) for c, t in streams(folder, others) if t["gesture"] == g])
                    for g, name in SIX.items()]
        mine = recognised(gestures, streams(folder, [held]), f"taught by the others, on {held}")
        per_teacher[held] = score(mine)
        runs += mine
    out = score(runs)
    out["by_held_out_teacher"] = {p: {"mean_recall": s["mean_recall"], "false_fire_rate": s["false_fire_rate"]}
                                  for p, s in per_teacher.items()}
    return out


OWN_STYLE = (("p09", "wind_it_up"), ("p07", "wind_it_up"), ("p04", "wind_it_up"), ("p06", "wind_it_up"),
             ("p05", "goggles"), ("p08", "shoot"))  # people p01-p03's teaching misses most


def teach_more(folder: Path, files: list[Path], completed: dict) -> dict:
    """A performer teaches their own style (docs/learned-gestures.md, "Teaching more"): one gesture
    learned again from the teachers' repetitions and the first half of the performer's recording of
    it (up to between its middle action points). Before and after: recall on the rest of their
    recordings of it (that second half, and any other recording), and false fires in the windows of
    all their recordings (the taught half left out). `files`: the protocol's six; `completed`: its
    events on each checked recording (before teaching more)."""
    gesture_of = {name: g for g, name in SIX.items()}
    taught = {g.name: g for g in map(load, files)}
    out = {}
    for person, name in OWN_STYLE:
        mine = streams(folder, [person])
        csv, truth = next((c, t) for c, t in mine if t["gesture"] == gesture_of[name])
        tags = truth["tags_s"]
        cut = (tags[len(tags) // 2 - 1] + tags[len(tags) // 2]) / 2
        later = {**truth, "tags_s": [tau for tau in tags if tau - BEFORE_S >= cut]}
        checked = [(c, later if c == csv else t) for c, t in mine]
        more = learn(name, [read_take(f"{csv}@0-{cut:.2f}", True)], before=taught_before(taught[name]))
        figures = []
        for runs in ([(t, completed[c]) for c, t in checked],
                     recognised([more if g.name == name else g for g in taught.values()], checked,
                                f"{person} teaches {name} more")):
            s = score(runs)
            figures.append((s["recall"][name], s["false_fire_rate"]))
        out[f"{person} {name}"] = {"recall_before": figures[0][0], "recall_after": figures[1][0],
                                   "false_fire_rate_before": figures[0][1], "false_fire_rate_after": figures[1][1],
                                   "taught_from": f"{csv.name}@0-{cut:.2f}"}
    return out


def kinder_motions(folder: Path) -> list[tuple[Path, dict]] | None:
    """Kinder-Gator's motions and their truth (kinder-gator-dev beside msrc12-dev), None without it."""
    kinder = folder.parent / "kinder-gator-dev"
    if not kinder.is_dir():
        return None
    return [(csv, json.loads((kinder / "truth" / (csv.stem + ".json")).read_text()))
            for csv in sorted(kinder.glob("*.csv"))]


def everyday(files: list[Path], motions: list[tuple[Path, dict]]) -> tuple[dict, dict[Path, list]]:
    """The six, taught by p01-p03, on other people doing other things: Kinder-Gator's adults and
    children (kinder-gator-dev beside msrc12-dev) walking, running, jumping, bowing, kicking, where
    nothing may fire, and performing the built-in dictionary (wave, hand_raise, swipes, click),
    where no learned gesture should either. Per group, the share of motions in which one completes,
    which fired where, and how many attempts are announced (IN_PROGRESS) a minute while nothing may
    fire; and each motion's COMPLETE events (for `counter_examples`' "before")."""
    gestures = [load(f) for f in files]
    shares: dict[str, list[int]] = collections.defaultdict(lambda: [0, 0])
    fired = collections.defaultdict(collections.Counter)
    null_attempts, null_s = 0, 0.0
    completed = {}
    for csv, truth in tracked(motions, "the six on Kinder-Gator's motions"):
        events, seconds = recognise(LearnedRecognizer(gestures, True), csv)
        done = completed[csv] = _completes(events)
        kind = "null" if truth["label"] is None else "dictionary"
        shares[f"{kind} {truth['group']}"][0] += bool(done)
        shares[f"{kind} {truth['group']}"][1] += 1
        fired[truth["label"] or "null"].update({name for _, name in done})
        if kind == "null":
            null_attempts += sum(state == "in_progress" for _, _, state in events)
            null_s += seconds
    return {"fired_share": {k: v[0] / v[1] for k, v in sorted(shares.items())},
            "motions": {k: v[1] for k, v in sorted(shares.items())},
            "fired_by_label": {label: dict(c) for label, c in sorted(fired.items()) if c},
            "null_in_progress_per_min": null_attempts / max(1e-9, null_s / 60)}, completed


COUNTER = ("throw", "p604")  # the gesture taught with counter-examples, and whose raised hands they are


def counter_examples(files: list[Path], folder: Path, motions: list[tuple[Path, dict]], checked: dict,
                     completed: dict[Path, list]) -> dict:
    """`issv learn --unlike` on the confusion `everyday` finds: throw learned again with one adult's
    two Kinder-Gator takes of a raised hand as counter-examples. Before and after: the other five
    people's raised hands and waves with a learned gesture, and the judged protocol on p04-p10
    (before: the protocol's figures, `checked`, and `everyday`'s events, `completed`; after: in
    process)."""
    name, person = COUNTER
    raises = [c for c, t in motions if t["person"] == person and t["label"] == "hand_raise"]
    others = [(c, t) for c, t in motions if t["label"] in ("hand_raise", "wave") and t["person"] != person]
    plain = [load(f) for f in files]
    unlike = [counter_example(read_take(str(c), True)) for c in raises]
    taught = [dataclasses.replace(g, unlike=unlike) if g.name == name else g for g in plain]
    after = score(recognised(taught, streams(folder, CHECKED), "p04-p10, with --unlike"))
    out = {"gesture": name, "unlike": [c.name for c in raises], "motions": len(others)}
    fired_after = recognised(taught, others, "raised hands and waves, with --unlike")
    for label, fired, s in (("before", [(t, completed[c]) for c, t in others], checked), ("after", fired_after, after)):
        out[label] = {"fired_share": sum(bool(e) for _, e in fired) / len(others), "mean_recall": s["mean_recall"],
                      "false_fire_rate": s["false_fire_rate"], "recall": s["recall"][name]}
    return out


def cost(files: list[Path], folder: Path) -> dict:
    """ms per frame for 10 learned gestures (six files, four of them again under new names)."""
    gestures = [load(f) for f in files]
    for extra, g in enumerate(gestures[:4]):
        twin = load(files[extra])
        twin.name = g.name + "_again"
        gestures.append(twin)
    start = time.process_time()
    Classifier.train(taught_repetitions(gestures[:6]))  # training itself, never a cache hit
    train_s = time.process_time() - start
    recognizer = LearnedRecognizer(gestures, True)
    frames = [f for c, t in streams(folder, ["p04"])[:4] for f in read_trajectories(c)]
    start = time.process_time()
    for f in frames:
        recognizer.update(f.t, f.hands, f.body)
    per_frame = (time.process_time() - start) / len(frames) * 1000
    return {"learned_gestures": len(gestures), "templates": int(len(recognizer.matcher.end)),
            "frames": len(frames), "ms_per_frame": per_frame, "train_six_cpu_s": train_s}


def main() -> None:
    args = parse_args(__doc__.splitlines()[0], lambda p: p.add_argument(
        "--skip-teachers", action="store_true", help="only the judged protocol on p04-p10"))
    folder = _data()
    with tempfile.TemporaryDirectory() as tmp:
        checked, files, learn_s, completed = protocol(folder, Path(tmp))
        timing = cost(files, folder)
        loose = loosened(files, folder, checked)
        bodiless = hands_only(folder)
        more = teach_more(folder, files, completed)
        motions = kinder_motions(folder)
        others, kinder_completed = (None, None) if motions is None else everyday(files, motions)
        unlike = None if motions is None else counter_examples(files, folder, motions, checked, kinder_completed)
    timing["learn_s_slowest_gesture"] = learn_s
    teachers = None if args.skip_teachers else teacher_side(folder)
    figures = {"checked_p04_p10": checked, "teachers_leave_one_out": teachers, "teach_more": more,
               "thresholds_scaled": loose, "hands_only": bodiless, "everyday_motions": others,
               "counter_examples": unlike, "cost": timing,
               "targets": {"mean_recall": 0.9, "worst_gesture_recall": 0.75, "worst_person_recall": 0.75,
                           "false_fire_rate": 0.10, "ms_per_frame": 1.0}}
    rows = []
    for label, s in (("p04-p10", checked), ("teachers (LOTO)", teachers)):
        if s is None:
            continue
        rows += [[label, g, r, ""] for g, r in s["recall"].items()]
        rows += [[label, f"person {p}", r, ""] for p, r in s["by_person"].items()]
        rows.append([label, "mean recall / false fires", s["mean_recall"], f"{s['false_fire_rate']:.3f}"])

    def overall(label: str, what: str, s: dict) -> list:
        return [label, f"{what}mean recall / false fires (worst person)", s["mean_recall"],
                f"{s['false_fire_rate']:.3f} ({s['worst_person_recall']:.2f})"]

    rows += [overall(half, "", s) for half, s in checked["halves"].items()]
    rows += [overall("hands only", f"{part}: ", s) for part, s in (("p04-p10", bodiless), *bodiless["halves"].items())]
    for which, label in (("all", "every gesture's threshold"), ("alone", f"{loose['gesture']}'s threshold alone")):
        rows += [["thresholds", f"{label} x{scale:g}: mean recall / false fires ({loose['gesture']}'s recall)",
                  p["mean_recall"], f"{p['false_fire_rate']:.3f} ({p['recall']:.2f})"]
                 for scale, p in sorted(loose[which].items())]
    rows += [["teach more", f"{case}: the rest of their recordings", m["recall_after"],
              f"{m['false_fire_rate_before']:.3f} -> {m['false_fire_rate_after']:.3f}; recall was {m['recall_before']:.2f}"]
             for case, m in more.items()]
    if others is None:
        print("bench.learned: no kinder-gator-dev beside msrc12-dev: everyday motions skipped", file=sys.stderr)
    else:
        rows += [["everyday motions", f"Kinder-Gator {kind} ({others['motions'][kind]} motions): a learned gesture fires",
                  "", f"{share:.3f}"] for kind, share in others["fired_share"].items()]
        rows.append(["everyday motions", "in_progress per minute of null motions", others["null_in_progress_per_min"], ""])
        b, a = unlike["before"], unlike["after"]
        rows.append(["--unlike", f"{unlike['gesture']} unlike {len(unlike['unlike'])} raised-hand takes: the others' "
                     f"raises and waves ({unlike['motions']}) with a learned gesture", "",
                     f"{b['fired_share']:.3f} -> {a['fired_share']:.3f}"])
        rows.append(["--unlike", f"p04-p10 mean recall ({unlike['gesture']}'s) / false fires, before -> after",
                     a["mean_recall"], f"{b['mean_recall']:.3f} ({b['recall']:.2f}) / {b['false_fire_rate']:.3f} -> "
                     f"{a['mean_recall']:.3f} ({a['recall']:.2f}) / {a['false_fire_rate']:.3f}"])
    ip = checked["in_progress"]
    rows.append(["p04-p10", "COMPLETEs announced by IN_PROGRESS", ip["announced_share"],
                 f"median {ip['lead_s_p50'] or 0:.2f} s before"])
    rows.append(["p04-p10", f"announced attempts (IN_PROGRESS, {ip['attempts']}) that complete",
                 ip["attempts_completed"], ""])
    rows.append(["cost", f"{timing['learned_gestures']} gestures, {timing['templates']} templates",
                 timing["ms_per_frame"], f"ms/frame; learn {learn_s:.1f} s; train six {timing['train_six_cpu_s']:.1f} s CPU"])
    report("Learned gestures (MSRC-12): recall within [-1.5, +1.0] s of the action point",
           figures, rows, ["set", "what", "recall / ms", "false-fire rate"], args.json)


if __name__ == "__main__":
    main()
