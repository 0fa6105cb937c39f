"""The `issv` command. Each subcommand is a module with `HELP`, `add_arguments(parser)` and
`main(args) -> int`: the host's own in host/commands, a plugin's handed over through the
`register_commands` hook; this file only dispatches to them."""
from __future__ import annotations

import argparse
import importlib
import pkgutil
import sys

import host.commands
from host import __version__
from host.errors import UserError
from host.plugins import command_name, default_registry


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="issv", description="Gesture-driven stage visuals.")
    parser.add_argument("--version", action="version", version=f"issv {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    commands = {command_name(m): m for m in (importlib.import_module(f"host.commands.{info.name}")
                                              for info in pkgutil.iter_modules(host.commands.__path__))}
    for name, registered in default_registry().commands.items():
        if name in commands:
            print(f"issv: plugin {registered.plugin!r} registers command {name!r}, which issv already has; "
                  "skipped", file=sys.stderr)
            continue
        commands[name] = registered.command
    for name in sorted(commands):
        module = commands[name]
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
