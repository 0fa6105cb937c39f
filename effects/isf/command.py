"""`issv isf FILE...`: renders each ISF file headless with its default values and says whether it
plays: one JSON line per file (`--json`) with file, ok, error, passes, kind, mean, std.

Image inputs get the demo's depth view (the synthetic performer through `depth-view`; a
transition's endImage the same in the turbo colour map), audio inputs a test tone. The show's
time runs at 30 frames a second whatever the rendering speed, so a run is repeatable. A file that
takes longer than --timeout (a shader that never ends) or crashes the driver is reported as not ok
and the next file runs (effects/isf/bounded.py).
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

NAME = "isf"
HELP = "render ISF shaders headless and report whether each plays (--json: one line per file)"
FPS = 30.0
TIMEOUT_S = 60.0  # the slowest Vidvox shader takes a few seconds at the defaults on a loaded 2-core llvmpipe


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("files", nargs="+", type=Path, metavar="FILE", help="ISF .fs files")
    parser.add_argument("--size", default="640x360", type=_size, help="render size WxH (default 640x360)")
    parser.add_argument("--frames", type=int, default=10, help="frames rendered per file (default 10)")
    parser.add_argument("--json", action="store_true", help="one JSON object per line")
    parser.add_argument("--snapshot-dir", type=Path, help="write the last frame of each file as NAME.png here")
    parser.add_argument("--timeout", type=float, default=TIMEOUT_S, help="seconds a file may take before it is "
                        f"reported as not ok and the next one runs (default {TIMEOUT_S:g})")


def _size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"--size {text!r}: expected WxH, e.g. 640x360") from None
    if not (0 < w <= 8192 and 0 < h <= 8192):
        raise argparse.ArgumentTypeError(f"--size {text!r}: width and height between 1 and 8192")
    return w, h


def main(args: argparse.Namespace) -> int:
    from effects.isf.bounded import BoundedTrial

    if args.frames < 1:
        sys.stderr.write("issv isf: --frames must be at least 1\n")
        return 2
    if not args.timeout > 0:
        sys.stderr.write("issv isf: --timeout must be more than 0 seconds\n")
        return 2
    if args.snapshot_dir:
        args.snapshot_dir.mkdir(parents=True, exist_ok=True)
    trial = BoundedTrial(args.size, args.timeout)
    results = []
    try:
        for path in args.files:
            snapshot = args.snapshot_dir / f"{path.stem}.png" if args.snapshot_dir else None
            result = trial.run(path, args.frames, snapshot)
            results.append(result)
            if args.json:
                sys.stdout.write(json.dumps(result) + "\n")
            else:
                status = "ok  " if result["ok"] else "FAIL"
                sys.stdout.write(f"{status} {result['kind']:<10} {result['passes']} pass(es) mean {result['mean']:.3f} "
                                 f"std {result['std']:.3f}  {path}\n")
                if result["error"]:
                    sys.stdout.write(f"     {result['error']}\n")
            sys.stdout.flush()
    finally:
        trial.close()
    ok = sum(r["ok"] for r in results)
    varied = sum(r["ok"] and r["std"] > 0.002 for r in results)
    sys.stderr.write(f"issv isf: {ok}/{len(results)} ok ({100 * ok / len(results):.1f} %), {varied} not a single "
                     f"colour ({100 * varied / len(results):.1f} %)\n")
    return 0 if ok == len(results) else 1
