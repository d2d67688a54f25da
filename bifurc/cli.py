"""The `bifurc` command line: a thin shell over the same functions a notebook calls.

Each subcommand lives in ``bifurc.commands.<name>`` with ``register(subparsers)``; a user
mistake (a bad parameter, option, scene or file) prints one line ``bifurc: error: ...`` on
stderr and exits 2, never a traceback. An existing output file is refused unless ``--force``.
The command line is recorded in every file's ``history`` attribute.
"""
from __future__ import annotations

import argparse
import importlib
import os
import shlex
import sys
import warnings

from maps.parameters import ParameterError
from maps.provenance import command

from ._version import __version__
from .storage.files import BadFileError

#: subcommand modules in bifurc.commands, each with register(subparsers); missing ones are skipped
COMMANDS = ["scenes", "params", "simulate", "diagram", "map", "orbit", "branch", "report", "accuracy", "verify", "study",
            "attractors", "explore"]

#: user-facing failures: one line on stderr, exit code 2 (any OSError: a file system refusing a file)
USER_ERRORS = (ParameterError, BadFileError, FileNotFoundError, FileExistsError, IsADirectoryError,
               NotADirectoryError, PermissionError, OSError)


#: options of 0.1 renamed in 0.2 (CHANGELOG's migration table): an unrecognized one is told its new name
RENAMED = {"--max-periods": "--budget"}


class UsageError(ValueError):
    """A malformed command line (unknown option, a value argparse cannot convert)."""


class _Parser(argparse.ArgumentParser):
    """argparse that raises :class:`UsageError` instead of printing usage and exiting."""

    def error(self, message):
        renamed = [f"{old} is now {new}" for old, new in RENAMED.items()
                   if "unrecognized arguments" in message and old in message.split()]
        raise UsageError(f"{message}{'; ' + ', '.join(renamed) if renamed else ''} (see `{self.prog} --help`)")


def build_parser() -> argparse.ArgumentParser:
    """The parser with every subcommand module that exists (subparsers inherit _Parser)."""
    parser = _Parser(prog="bifurc",
                     description="Bifurcation analysis of the electro-vibro-impact system (heyoka).")
    parser.add_argument("--version", action="version", version=f"bifurc {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMANDS:
        modname = f"bifurc.commands.{name}"
        try:
            module = importlib.import_module(modname)
        except ModuleNotFoundError as exc:
            if exc.name == modname:  # not written yet; any other missing import is a real error
                continue
            raise
        module.register(sub)
    return parser


def _warn(message, category, filename, lineno, file=None, line=None) -> None:
    """Warnings as one line each: ``bifurc: warning: ...``."""
    print(f"bifurc: warning: {' '.join(str(message).split())}", file=sys.stderr)


def _fail(message) -> int:
    if isinstance(message, OSError) and message.strerror and message.filename:
        message = f"{message.filename}: {message.strerror.lower()}"   # "[Errno 30] ..." in words
    print(f"bifurc: error: {' '.join(str(message).split())}", file=sys.stderr)
    return 2


def _file_backend() -> None:
    """Figures go to files: the non-interactive Agg backend, unless pyplot already runs
    (main called from a notebook keeps the notebook's backend)."""
    if "matplotlib.pyplot" not in sys.modules:
        import matplotlib
        matplotlib.use("Agg")


def main(argv=None) -> int:
    """Run the command line on ``argv`` (default ``sys.argv[1:]``); return the exit code."""
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except UsageError as exc:
        return _fail(exc)
    except SystemExit as exc:  # --help, --version
        return exc.code if isinstance(exc.code, int) else 0
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    _file_backend()
    try:
        with command(shlex.join(["bifurc", *argv])), warnings.catch_warnings():
            warnings.showwarning = _warn
            code = int(args.func(args) or 0)
            sys.stdout.flush()  # a closed pipe shows here, not at interpreter exit
            return code
    except BrokenPipeError:  # e.g. `bifurc report d.nc | head`: the reader left; say nothing more
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141  # 128 + SIGPIPE, as a shell reports a writer stopped by a closed pipe
    except (UsageError, *USER_ERRORS) as exc:
        return _fail(exc)
    except KeyboardInterrupt as exc:
        print(f"bifurc: {exc}" if str(exc) else "bifurc: interrupted", file=sys.stderr)  # sweeps name what they kept
        return 130


if __name__ == "__main__":
    sys.exit(main())
