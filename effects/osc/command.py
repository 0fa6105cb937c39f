"""`issv osc-schema`: print the OSC address scheme the `osc` effect sends (README.md, OSC).

A command of the OSC effect's plugin (registered through `register_commands`); light to import.
"""
from __future__ import annotations

import argparse

NAME = "osc-schema"
HELP = "print the OSC address scheme (or a preset's: osceleton, synapse, custom templates)"
SCHEMES = ("issv", "osceleton", "synapse", "custom")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("scheme", nargs="?", default="issv", choices=SCHEMES,
                   help="which scheme to describe (default: issv, the default scheme)")


def main(args: argparse.Namespace) -> int:
    from effects.osc.effect import OscEffect

    print(OscEffect.describe(args.scheme), end="")
    return 0
