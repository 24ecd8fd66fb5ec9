"""``puckboard bench``: how fast the blackboard, the arbiter and the simulator run here."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from .checks import check_writable
from .errors import CliError


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
    parser.add_argument("--out", type=Path, metavar="FILE", help="also write all results as JSON")
    suite = parser.add_argument_group(
        "suite options", "passed to the suites that take them (an error if none selected does)"
    )
    suite.add_argument("--seeds", type=int, nargs="+", metavar="N", help="estimation: seeds")
    suite.add_argument("--gyro-noise", type=float, help="estimation: simulated gyro σ (rad/s)")
    suite.add_argument("--gyro-bias", type=float, help="estimation: simulated gyro offset (rad/s)")
    suite.add_argument(
        "--settle", type=float, help="estimation: seconds standing still first (gyro offset)"
    )
    suite.add_argument(
        "--cases",
        choices=("all", "line-follow"),
        help="estimation: line-follow runs only its three laps (quicker)",
    )
    suite.add_argument("--plot", type=Path, help="estimation: draw line-follow here")
    suite.add_argument(
        "--plot-contact", type=Path, help="estimation: draw the stock two-robot pass here"
    )
    suite.add_argument(
        "--durations",
        type=Path,
        metavar="FILE",
        help="sweep: model the scheduling of the episodes in this sweep --out file",
    )
    suite.add_argument(
        "--server",
        choices=("thread", "process"),
        help="coppeliasim: serve from a thread of this process or a separate process",
    )
    parser.set_defaults(func=main)


#: Suite options on the command line (argparse dest == the suite's keyword argument).
SUITE_OPTIONS = (
    "seeds", "gyro_noise", "gyro_bias", "settle", "cases", "plot", "plot_contact", "server",
    "durations",
)  # fmt: skip


def main(args: argparse.Namespace) -> int:
    from ..bench import DEFAULT_SUITES, SUITES, run_suites, suite_options
    from ..bench.report import format_results

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
    if args.out is not None:
        check_writable(args.out, "--out")
    options = {k: getattr(args, k) for k in SUITE_OPTIONS if getattr(args, k) is not None}
    taken = set().union(*(suite_options(n) for n in names))
    for key in options:
        if key not in taken:
            flag = "--" + key.replace("_", "-")
            wanting = [n for n in SUITES if key in suite_options(n)]
            raise CliError(
                f"{flag} is an option of suite {', '.join(wanting) or '(none)'}, "
                f"not of {', '.join(names)}; add --suite {wanting[0] if wanting else 'NAME'}"
            )
    if not args.json:
        print(f"running {', '.join(names)} ...", file=sys.stderr, flush=True)
    try:
        results = run_suites(names, args.steps, options)
    except ValueError as exc:
        raise CliError(str(exc)) from None
    _refuse_if_nothing_ran(results)
    if args.out is not None:
        args.out.write_text(json.dumps(results, indent=1, default=str), encoding="utf-8")
    if args.json:
        print(json.dumps(results, indent=None, default=str))
    else:
        print(format_results(results))
    return 0


def _refuse_if_nothing_ran(results: dict[str, Any]) -> None:
    """When every suite asked for was skipped nothing was measured: that is an error
    (status 2) that says how to install what is missing, not a report of nothing."""
    suites = results.get("suites", {})
    reasons = [r["skipped"] for r in suites.values() if isinstance(r, dict) and "skipped" in r]
    if suites and len(reasons) == len(suites):
        raise CliError("nothing was measured: " + "; ".join(str(r) for r in reasons))
