"""`issv learn NAME EXAMPLE...`: teach issv a gesture by performing it (docs/learned-gestures.md).

    issv learn goggles take1.csv take2.csv@3.5-20 --mirrored -o goggles.gesture.json
    issv learn --show goggles.gesture.json          # what was learned, and a PNG of the repetitions
    issv learn bow --profile stage.toml --repetitions 5   # live, from the profile's source and backend
    issv learn goggles goggles.gesture.json take3.csv --mirrored   # teach it more: a new performer added
    issv learn throw throws.csv --unlike raise.csv --mirrored   # and what it is not: a raised hand

Each example holds one or more repetitions separated by rest or stillness; the learner finds them,
says how many and how alike they are, and names a repetition far from the others by its time. An
example may also be a learned-gesture file: its repetitions are learned again with the new ones.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from host.errors import UserError
from host.learned.examples import read_take
from host.learned.gesture_file import LearnedGesture, load
from host.learned.learner import (STYLE_MIN, counter_example, examples_left_out, far_off, hands_used, held_by_ceiling,
                                  learn, taught_before, typical_length, unlike_before)
from host.learned.loops import LoopCheck
from host.learned.matcher import taught_repetitions

HELP = "learn a gesture from examples of it (CSV trajectories, .npz clips, .mcap recordings)"
_HANDS = {"both": "both hands", "left": "the left hand", "right": "the right hand"}


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("name", nargs="?", help="the gesture's name, as effects and OSC will see it")
    p.add_argument("examples", nargs="*", metavar="EXAMPLE",
                   help="FILE or FILE@START-END (seconds): .csv hand trajectories, .npz depth clips, .mcap recordings; "
                   "or a learned-gesture .json, whose repetitions are learned again with the new ones")
    p.add_argument("--unlike", nargs="+", action="extend", default=[], metavar="EXAMPLE",
                   help="counter-examples: takes of motions the gesture must not be taken for (a raised hand for a "
                   "throw that ends up high), same forms as EXAMPLE, kept whole in the file")
    p.add_argument("--mirrored", action="store_true",
                   help="CSV coordinates come from a mirrored image: +x is the performer's right")
    p.add_argument("-o", "--output", type=Path, help="where to write the gesture (default: NAME.gesture.json)")
    p.add_argument("--backend", default="openiss", help="backend that tracks hands in .npz clips (default: openiss)")
    p.add_argument("--show", type=Path, metavar="FILE", help="print what FILE learned and plot its repetitions (PNG)")
    p.add_argument("--profile", type=Path,
                   help="teach live: take the repetitions from this profile's source and backend")
    p.add_argument("--repetitions", type=int, default=5, help="live: how many repetitions to take (default: 5)")
    p.add_argument("--seconds", type=float, default=3.0, help="live: seconds for each repetition (default: 3)")


def _held(g: LearnedGesture) -> list[str]:
    """A line when the threshold was held below what the repetitions give (learner.threshold)."""
    loose = held_by_ceiling(g)
    if loose is None:
        return []
    return [f"  threshold held at {g.threshold:.3f}: the repetitions are far apart (they give {loose:.3f}, at which "
            "almost any motion would pass for the gesture); re-record them alike, several in one take, and check "
            "that the tracker keeps the hands (issv track)"]


def describe(g: LearnedGesture) -> str:
    durations = [r.duration for r in g.repetitions]
    scores = [r.score for r in g.repetitions if r.score is not None]
    lines = [f"{g.name}: {len(g.repetitions)} repetitions, {np.median(durations):.2f} s typical "
             f"({min(durations):.2f}-{max(durations):.2f} s), hands: {g.hands}",
             f"  threshold {g.threshold:.3f} (a performance must come this close; override per gesture in a "
             f"profile), completes {g.fires_at:.0%} of the way through"]
    lines += _held(g)
    loops = LoopCheck([g], taught_repetitions([g])).describe(0)
    if loops:
        lines.append(f"  loops: {loops}; a performance must loop too, facing the same way (docs/learned-gestures.md)")
        if g.hands == "both":
            lines.append("  also recognised rolled with either arm alone, on a loop as big as a taught hand's")
    if g.unlike:
        lines.append(f"  unlike: {len(g.unlike)} counter-examples, {sum(u.duration for u in g.unlike):.1f} s "
                     f"({', '.join(u.source for u in g.unlike)}): motions it is not")
    if scores:
        lines.append(f"  consistency: each repetition's distance to the others of its example, "
                     f"median {np.median(scores):.3f}, worst {max(scores):.3f} (body units)")
    for r in g.repetitions:
        score = f"  {r.score:.3f}" if r.score is not None else ""
        lines.append(f"    {r.source} {r.start:.2f}-{r.end:.2f} s{score}")
    return "\n".join(lines)


def plot(g: LearnedGesture, path: Path) -> None:
    """The repetitions over each other: each hand's x, y, z against the share of the repetition,
    one colour per example (a performer taught more shows as a style of its own)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(2, 3, figsize=(12, 6), sharex=True)
    labels = [f"{hand} {axis}" for hand in ("left", "right") for axis in "xyz"]
    colours = {source: f"C{i % 10}" for i, source in enumerate(dict.fromkeys(r.source for r in g.repetitions))}
    for r in g.repetitions:
        share = np.linspace(0, 1, len(r.postures))
        for c, ax in enumerate(axes.flat):
            ax.plot(share, r.postures[:, c], color=colours[r.source], alpha=0.6, lw=1)
    for c, ax in enumerate(axes.flat):
        ax.set_title(labels[c], fontsize=9)
        ax.axvline(g.fires_at, color="k", ls=":", lw=1)
    legend = len(colours) > 1
    if legend:
        fig.legend([plt.Line2D([], [], color=colour) for colour in colours.values()],
                   [Path(source).name for source in colours], loc="lower center", ncol=min(4, len(colours)),
                   fontsize=8)
    fig.suptitle(f"{g.name}: {len(g.repetitions)} repetitions (body units; dotted: where it completes)")
    fig.tight_layout(rect=(0, 0.08 if legend else 0, 1, 1))
    try:
        fig.savefig(path, dpi=80)
    except OSError as error:
        raise UserError(f"{path}: cannot write the plot ({error.strerror})") from None
    finally:
        plt.close(fig)


def _live(args: argparse.Namespace) -> list:
    from host import profile as profiles
    from host.assemble import make_backend
    from host.learned.live import teach
    if args.repetitions < 2:
        raise UserError("issv learn: --repetitions must be at least 2 (the threshold comes from how they differ)")
    backend = make_backend(profiles.load(args.profile), realtime=True)
    ask = input if sys.stdin.isatty() else None
    with backend.inner if hasattr(backend, "inner") else backend:
        return teach(backend, args.repetitions, args.seconds, sys.stdout, ask)


def left_out(gesture: LearnedGesture) -> list[str]:
    """What the learner made of lengths unlike the others', in words: an example learned at a pace of
    its own; an example of which no repetition was learned, said once, with why (other hands, or too
    few repetitions for a pace of their own); any other repetition left out by its time, so the artist
    can re-record it."""
    others = [r for r in gesture.repetitions if r.source not in gesture.paces]
    typical = typical_length(others or gesture.repetitions)
    lines = [f"  another pace: {source} ({pace:.1f} s, the others {typical:.1f} s typically), learned as a style "
             "of the gesture" for source, pace in gesture.paces.items()]
    whole = examples_left_out(gesture)
    for source in whole:
        reps = [r for r in gesture.left_out if r.source == source]
        lengths = [r.duration for r in reps]
        hands = hands_used(reps)[0]
        why = (f"made with {_HANDS[hands]}, the others with {_HANDS[gesture.hands]}: another gesture? Teach it as a "
               f"gesture of its own (issv learn NAME {source})" if hands != gesture.hands else
               f"another pace of the gesture? Perform it at the others' pace, or at least {STYLE_MIN} times at its own")
        lines.append(f"  left out: all {len(lengths)} repetitions of {source} ({min(lengths):.1f}-{max(lengths):.1f} s, "
                     f"the others {typical:.1f} s typically): {why}")
    for r in gesture.left_out:
        if r.source not in whole:
            why = "two run together?" if r.duration > typical else "cut short, or a twitch?"
            lines.append(f"  left out: {r.source} {r.start:.1f}-{r.end:.1f} s lasts {r.duration:.1f} s, unlike the "
                         f"others ({why})")
    return lines


def main(args: argparse.Namespace) -> int:
    if args.show is not None:
        gesture = load(args.show)
        print(describe(gesture))
        png = args.show.with_suffix(".png")
        plot(gesture, png)
        print(f"plot: {png}")
        return 0
    if not args.name:
        raise UserError("issv learn: name the gesture and give examples of it: issv learn NAME TAKE.csv ...")
    if not args.examples and args.profile is None:
        raise UserError(f"issv learn {args.name}: give examples (TAKE.csv, CLIP.npz, REC.mcap) or --profile to "
                        "teach live")
    files = {e: load(e) for e in args.examples if Path(e).suffix.lower() == ".json"}
    before = {e: taught_before(g) for e, g in files.items()}
    takes = [read_take(e, args.mirrored, args.backend) for e in args.examples if e not in before]
    unlike = [u for g in files.values() for u in unlike_before(g)] + \
        [counter_example(read_take(e, args.mirrored, args.backend)) for e in args.unlike]
    if args.profile is not None:
        takes += _live(args)
    gesture = learn(args.name, takes, before=[r for reps in before.values() for r in reps], unlike=unlike)
    output = args.output or Path(f"{args.name}.gesture.json")
    gesture.save(output)
    for source, reps in before.items():
        print(f"{source}: {len(reps)} repetitions taught before")
    for source, count in gesture.found.items():
        print(f"{source}: {count} repetition{'s' * (count != 1)} found")
    for u in gesture.unlike:
        print(f"{u.source}: unlike it, {u.duration:.1f} s learned as none")
    for line in left_out(gesture):
        print(line)
    for r in far_off(gesture):
        print(f"  far from the others: {r.source} {r.start:.1f}-{r.end:.1f} s (score {r.score:.3f}); "
              "re-record it if it was a wrong take")
    print("\n".join(describe(gesture).splitlines()[:1] + _held(gesture)))
    print(f"wrote {output}")
    return 0
