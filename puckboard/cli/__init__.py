"""The ``puckboard`` command line.

Each subcommand lives in its own module ``puckboard.cli.<name>`` with a
``register(subparsers)`` function that adds its parser and sets ``func``. Those modules
import only ``argparse`` at the top and load the heavy parts inside ``func``, so
``puckboard --help`` stays instant. No core module imports this package.
"""

from __future__ import annotations

import argparse
import difflib
import importlib
import logging
import os
import sys
from collections.abc import Sequence

from .._version import __version__
from .errors import CliError
from .parsing import _ArgumentError, _SubcommandParser

__all__ = ["COMMANDS", "build_parser", "main"]

#: Subcommands in the order ``--help`` lists them.
COMMANDS: tuple[str, ...] = (
    "run",
    "bench",
    "serve",
    "emulate",
    "sweep",
    "sensitivity",
    "tune",
    "transfer",
    "challenge",
    "plot",
    "replay",
    "monitor",
    "tree",
    "scenes",
    "profiles",
    "calibrate",
    "examples",
    "docs",
)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="puckboard",
        description="Behaviour-based control of the e-puck: simulate, serve, drive and inspect.",
    )
    parser.add_argument("--version", action="version", version=f"puckboard {__version__}")
    parser.add_argument(
        "-v", "--verbose", action="count", default=0, help="more log output (-vv for debug)"
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_SubcommandParser)
    for name in COMMANDS:
        try:
            module = importlib.import_module(f"{__name__}.{name}")
        except ModuleNotFoundError as exc:
            if exc.name == f"{__name__}.{name}":
                continue  # subcommand not part of this build
            raise
        module.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    from ..sweep.signals import spare_native_threads

    # before anything imports numpy (building the parser reads the settings table, whose
    # modules do): see sweep/signals.py
    spare_native_threads()
    parser = build_parser()
    try:
        args, extras = parser.parse_known_args(argv)
    except _ArgumentError as exc:
        print(f"{exc.prog}: error: {exc}", file=sys.stderr)
        return 2
    if extras:
        command = getattr(args, "command", None)
        if command is None:
            parser.error(f"unrecognized arguments: {' '.join(extras)}")
        print(f"puckboard {command}: error: {_unrecognized(parser, command, extras)}",
              file=sys.stderr)  # fmt: skip
        return 2
    level = logging.WARNING - 10 * min(args.verbose, 2)
    logging.basicConfig(level=level, format="%(levelname)s %(name)s: %(message)s")
    if not getattr(args, "func", None):
        parser.print_help()
        return 0
    try:
        return int(args.func(args) or 0)
    except CliError as exc:
        if exc.details:
            print(exc.details.rstrip("\n"), file=sys.stderr)
        print(f"puckboard {args.command}: error: {exc}", file=sys.stderr)
        return exc.status
    except KeyboardInterrupt as exc:
        # Ctrl-C, or SIGTERM where a command stops on it in the same orderly way (it then
        # raises a KeyboardInterrupt that says so: puckboard.sweep.signals.Terminated)
        print(f"puckboard {args.command}: {getattr(exc, 'reason', 'interrupted')}", file=sys.stderr)
        return int(getattr(exc, "exit_status", 130))
    except BrokenPipeError:
        # the reader went away ('puckboard profiles | head'): stop quietly, as Unix tools
        # do, and keep Python from complaining again when it flushes stdout at exit
        _silence_stdout()
        return 0


def _unrecognized(parser: argparse.ArgumentParser, command: str, extras: list[str]) -> str:
    """What the subcommand did not take, said by the subcommand (argparse leaves it to the
    top-level parser, whose usage names no option of the command): an unknown option
    with the one that was probably meant, an extra value as one too many (``run A B``)."""
    options: list[str] = []
    for action in parser._actions:  # the subcommand's own options
        if isinstance(action, argparse._SubParsersAction):
            options = [o for a in action.choices[command]._actions for o in a.option_strings]
    help_hint = f"see 'puckboard {command} --help'"
    first = extras[0]
    if first.startswith("-"):
        close = difflib.get_close_matches(first.split("=")[0], options, n=1)
        meant = f" (did you mean {close[0]}?)" if close else ""
        return f"no option {first}{meant}; {help_hint}"
    many = "s" if len(extras) > 1 else ""
    return f"unexpected argument{many} {' '.join(map(repr, extras))} (one too many); {help_hint}"


def _silence_stdout() -> None:
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):
        pass  # not a real file (a test's capture): nothing left to flush


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
