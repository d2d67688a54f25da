"""The `bifurc` command line: a thin shell over the same functions a notebook calls."""
from __future__ import annotations

import argparse
import importlib
import sys

from maps.parameters import ParameterError

from . import __version__

#: subcommand modules in bifurc.commands, each with register(subparsers)
COMMANDS = ["scenes", "simulate", "diagram", "report", "accuracy", "stability", "study"]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="bifurc", description="Bifurcation analysis of the electro-vibro-impact system (heyoka).")
    parser.add_argument("--version", action="version", version=f"bifurc {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMANDS:
        modname = f"bifurc.commands.{name}"
        try:
            module = importlib.import_module(modname)
        except ModuleNotFoundError as exc:
            if exc.name == modname:
                continue
            raise
        module.register(sub)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        return int(args.func(args) or 0)
    except (ParameterError, FileNotFoundError, FileExistsError) as exc:
        print(f"bifurc: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("bifurc: interrupted; completed work is kept on disk where the command streams it",
              file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
