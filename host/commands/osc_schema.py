"""`issv osc-schema`: print the OSC address scheme the `osc` effect sends (README.md, OSC)."""
from __future__ import annotations

import argparse

from host.errors import UserError
from host.plugins import default_registry

NAME = "osc-schema"
HELP = "print the OSC address scheme (or a preset's: osceleton, synapse, custom templates)"
SCHEMES = ("issv", "osceleton", "synapse", "custom")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("scheme", nargs="?", default="issv", choices=SCHEMES,
                   help="which scheme to describe (default: issv, the default scheme)")


def main(args: argparse.Namespace) -> int:
    entry = default_registry().get("effects", "osc")
    if entry is None:
        raise UserError("issv: the `osc` effect is not installed (`issv list` shows what is)")
    print(entry.cls.describe(args.scheme), end="")
    return 0
