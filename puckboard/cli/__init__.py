"""The ``puckboard`` command line.

Each subcommand lives in its own module ``puckboard.cli.<name>`` with a
``register(subparsers)`` function that adds its parser and sets ``func``. Those modules
import only ``argparse`` at the top and load the heavy parts inside ``func``, so
``puckboard --help`` stays instant. No core module imports this package.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import sys
from collections.abc import Sequence

from .._version import __version__

__all__ = ["COMMANDS", "main"]

#: Subcommands in the order ``--help`` lists them.
COMMANDS: tuple[str, ...] = (
    "run",
    "bench",
    "serve",
    "emulate",
    "sweep",
    "plot",
    "monitor",
    "tree",
    "scenes",
    "profiles",
    "examples",
    "docs",
)


class CliError(Exception):
    """Bad input on the command line: printed as one line, exit status 2."""


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="puckboard",
        description="Behaviour-based control of the e-puck: simulate, serve, drive and inspect.",
    )
    parser.add_argument("--version", action="version", version=f"puckboard {__version__}")
    parser.add_argument(
        "-v", "--verbose", action="count", default=0, help="more log output (-vv for debug)"
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
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
    parser = build_parser()
    args = parser.parse_args(argv)
    level = logging.WARNING - 10 * min(args.verbose, 2)
    logging.basicConfig(level=level, format="%(levelname)s %(name)s: %(message)s")
    if not getattr(args, "func", None):
        parser.print_help()
        return 0
    try:
        return int(args.func(args) or 0)
    except CliError as exc:
        print(f"puckboard {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"puckboard {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
