"""`issv calibrate PROFILE`: camera-to-stage calibration and keystone, saved into the profile.

From a points file (`--points FILE.csv`, >= 4 pairs of camera point -> stage pixel), from
`--keystone` corners, or interactively in the window: drag the four corners, then hold a hand
still on each projected target. The profile keeps its comments and layout: only
`output.calibration` and `output.keystone` are (re)written, with tomlkit, which edits TOML
documents in place, where tomllib only reads and tomli-w would re-emit the file without them.
"""
from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import tomlkit

from host import profile as profiles
from host.errors import UserError
from host.render.calibration import apply, check_keystone, homography, read_points

HELP = "camera-to-stage calibration and keystone: from a points file, or interactively in the window"


def corner(text: str) -> tuple[float, float]:
    try:
        x, y = (float(v) for v in text.split(","))
        return (x, y)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected X,Y (fractions of the output, e.g. 0.05,0.02), got {text!r}") from None


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("profile", help="the profile to calibrate (its [output] is rewritten in place)")
    p.add_argument("--points", metavar="FILE.csv",
                   help="point pairs: header u,v,stage_x,stage_y (depth pixels) or x,y,z,stage_x,stage_y (mm)")
    p.add_argument("--keystone", type=corner, nargs=4, metavar="X,Y",
                   help="corners top-left top-right bottom-right bottom-left, as output fractions")
    p.add_argument("--reset", action="store_true", help="remove the calibration and the keystone")


def save(path: Path, values: dict[str, object]) -> None:
    """Sets (or removes, for None) keys of the profile's [output] table, keeping everything else."""
    doc = tomlkit.parse(path.read_text(encoding="utf-8"))
    if "output" not in doc:
        doc.add("output", tomlkit.table())
    output = doc["output"]
    for key, value in values.items():
        if value is None:
            output.pop(key, None)
        else:
            output[key] = value
    path.write_text(tomlkit.dumps(doc), encoding="utf-8")


def rounded(m: np.ndarray) -> list[list[float]]:
    return [[float(f"{v:.9g}") for v in row] for row in np.asarray(m)]


def source_intrinsics(prof: profiles.Profile):
    """The source's intrinsics, to turn camera millimetres into depth pixels."""
    if prof.source is None:
        return None
    source = prof.source.cls(prof.source.options)
    source.open()
    try:
        return getattr(source, "intrinsics", None)
    finally:
        source.close()


def from_points(prof: profiles.Profile, points: str) -> list[list[float]]:
    cam, stage = read_points(points, lambda: source_intrinsics(prof))
    try:
        h = homography(cam, stage)
    except ValueError as error:
        raise UserError(f"{points}: {error}") from None
    residual = np.linalg.norm(apply(h, cam) - stage, axis=1)
    print(f"calibration from {len(cam)} point pairs: residual mean {residual.mean():.2f} px, "
          f"max {residual.max():.2f} px")
    return rounded(h)


def main(args: argparse.Namespace) -> int:
    path = Path(args.profile)
    prof = profiles.load(path)
    values: dict[str, object] = {}
    if args.reset:
        values = {"calibration": None, "keystone": None}
    if args.keystone:
        try:
            values["keystone"] = [list(c) for c in check_keystone(args.keystone)]
        except UserError as error:
            raise UserError(f"--keystone: {error}") from None
    if args.points:
        values["calibration"] = from_points(prof, args.points)
    if not values:
        from host.render.interactive import calibrate_interactively
        values = calibrate_interactively(prof)
        if not values:
            print("calibration cancelled: the profile is unchanged")
            return 0
    save(path, values)
    profiles.load(path)  # what was written must still be a valid profile
    print(f"{path}: saved output.{' and output.'.join(sorted(values))}")
    return 0
