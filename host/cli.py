"""The `issv` command. Each subcommand is a module in host/commands with `HELP`,
`add_arguments(parser)` and `main(args) -> int`; this file only dispatches to them."""
from __future__ import annotations

import argparse
import importlib
import pkgutil
import sys

import host.commands
from host import __version__
from host.errors import UserError


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="issv", description="Gesture-driven stage visuals.")
    parser.add_argument("--version", action="version", version=f"issv {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for info in sorted(pkgutil.iter_modules(host.commands.__path__), key=lambda m: m.name):
        module = importlib.import_module(f"host.commands.{info.name}")
        name = getattr(module, "NAME", info.name.replace("_", "-"))
        command = sub.add_parser(name, help=module.HELP, description=module.HELP)
        module.add_arguments(command)
        command.set_defaults(handler=module.main)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return int(args.handler(args) or 0)
    except UserError as error:
        print(error, file=sys.stderr)
        return error.status
    except BrokenPipeError:
        return 0


if __name__ == "__main__":
    sys.exit(main())
