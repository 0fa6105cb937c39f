"""`issv check PROFILE`: validate a profile without running it."""
from __future__ import annotations

import argparse

from host import profile as profiles

HELP = "validate a profile: every problem on one line naming the key, exit status 2 if any"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("profile", nargs="+", help="profile TOML file(s)")


def main(args: argparse.Namespace) -> int:
    for path in args.profile:
        prof = profiles.load(path)
        for warning in prof.warnings:
            print(f"warning: {warning}")
        effects = ", ".join(r.ref.name for r in prof.effects) or "no effects"
        source = f"{prof.source.ref.name} -> " if prof.source else ""
        print(f"{path}: ok ({source}{prof.backend.ref.name} -> {effects})")
    return 0
