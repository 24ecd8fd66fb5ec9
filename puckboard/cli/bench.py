"""``puckboard bench``: how fast the blackboard, the arbiter and the simulator run here."""

from __future__ import annotations

import argparse
import json
import sys

from . import CliError


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    parser = subparsers.add_parser(
        "bench",
        help="measure blackboard, arbiter and simulator speed",
        description=(
            "Run benchmark suites and print medians over repeats. Default suites: core "
            "(blackboard and arbiter next to py_trees) and sim (the two-robot pass with the "
            "full stack). Figures are for comparison on one machine, not pass/fail."
        ),
    )
    parser.add_argument(
        "--suite",
        action="append",
        metavar="NAME",
        help="suite to run (repeatable); see --list. Default: core and sim",
    )
    parser.add_argument("--list", action="store_true", help="list the suites and exit")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument(
        "--steps",
        type=int,
        metavar="N",
        help="steps (or calls) per repeat; fewer is quicker but noisier",
    )
    parser.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    from ..bench import DEFAULT_SUITES, SUITES, format_results, run_suites

    if args.list:
        for name, target in SUITES.items():
            print(f"{name:<12} {target}")
        return 0
    names = args.suite or list(DEFAULT_SUITES)
    unknown = [n for n in names if n not in SUITES]
    if unknown:
        raise CliError(f"unknown suite {unknown[0]!r}; suites: {', '.join(SUITES)} (see --list)")
    if args.steps is not None and args.steps < 1:
        raise CliError(f"--steps must be a positive number, got {args.steps}")
    if not args.json:
        print(f"running {', '.join(names)} ...", file=sys.stderr, flush=True)
    results = run_suites(names, args.steps)
    if args.json:
        print(json.dumps(results, indent=None, default=str))
    else:
        print(format_results(results))
    return 0
