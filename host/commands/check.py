"""`issv check PROFILE`: validate a profile without running it."""
from __future__ import annotations

import argparse

from host import profile as profiles
from host.assemble import make_backend, make_effects
from host.errors import ProfileError, UserError

HELP = "validate a profile: every problem on one line naming the key, exit status 2 if any"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("profile", nargs="+", help="profile TOML file(s)")


def main(args: argparse.Namespace) -> int:
    for path in args.profile:
        prof = profiles.load(path)
        try:  # constructing (not opening) the plugins reads the files they name, e.g. a choreography
            make_backend(prof, realtime=False)
            make_effects(prof)
        except UserError as error:
            raise ProfileError([str(error)]) from None
        for warning in prof.warnings:
            print(f"warning: {warning}")
        effects = ", ".join(r.ref.name for r in prof.effects) or "no effects"
        source = f"{prof.source.ref.name} -> " if prof.source else ""
        print(f"{path}: ok ({source}{prof.backend.ref.name} -> {effects})")
    return 0
