"""`issv new-effect NAME`: scaffold an installable effect package."""
from __future__ import annotations

import argparse
from pathlib import Path

from host.errors import UserError
from host.plugins import default_registry
from host.scaffold import check_name, scaffold

NAME = "new-effect"
HELP = "write a new effect package (pyproject, effect class, test, README) ready to pip install"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("name", help="the effect's name in profiles, e.g. hand-glow")
    p.add_argument("-o", "--output", type=Path, default=Path("."), metavar="DIR",
                   help="where to create the issv-NAME folder (default: here)")


def main(args: argparse.Namespace) -> int:
    names = check_name(args.name)
    taken = default_registry().get("effects", names.name)
    if taken is not None:
        raise UserError(f"issv new-effect: an effect named {names.name!r} is already installed "
                        f"(plugin {taken.plugin!r}); pick another name")
    root = scaffold(names.name, args.output)
    print(f"created {root}/\n"
          f"next:  pip install -e {root}   then   issv list   (it shows {names.name!r} under effects)\n"
          f"edit:  {root / names.module / '__init__.py'}")
    return 0
