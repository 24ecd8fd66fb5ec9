"""``puckboard transfer``: a controller's pass rate on models it was not designed on.

For each controller × profile × scene: the band on the design model (the scene with
plausible robots, as the published bands), the band on each held-out family
(:mod:`puckboard.transfer.families`), each with its 95 % Wilson interval, and each
continuous perturbation's robustness radius on a grid declared up front. Runs on the
sweep machinery: all local cores or a Dask cluster, ``--out`` rows to resume from,
Ctrl-C keeps what ran. See ``docs/transfer.md``.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..sweep.defaults import TRANSFER_SEEDS
from .checks import check_plot_file
from .errors import CliError
from .experiment_options import (
    add_controllers,
    add_duration,
    add_fixed_sets,
    add_out,
    add_quiet,
    add_where_to_run,
    check_numbers,
    execute,
    exit_status,
    fixed_sets,
    open_out,
    run_options,
    wall_time,
    with_executor,
)

if TYPE_CHECKING:
    from ..sweep.executors import SweepExecutor


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    parser = subparsers.add_parser(
        "transfer",
        help="judge controllers on models they were not designed on: held-out bands and "
        "robustness radii",
        description=(
            "For each controller, profile and scene, run the same seeds on the design model "
            "(the scene with plausible robots, --variation plausible, as the published "
            "bands) and on each held-out family of models (noise at twice the scene's, and "
            "the families listed in docs/transfer.md), and report each pass rate with its "
            "95 % Wilson interval. For each continuous perturbation (a family with a grid of "
            "scales, declared before anything runs) report its robustness radius: the "
            "furthest scale up to which the pass rate stays at or above 95 % (by point "
            "estimate, with the interval of the point that supports it; --json also has the "
            "radius by the interval's lower bound). Runs on all local cores or a Dask "
            "cluster; --out keeps one row per episode, and the same command resumes from it."
        ),
        epilog=(
            "Example: puckboard transfer two-robot-pass two-robot-pass-bend --controller "
            "robust --controller improved --profile epuck --profile epuck-vrep --out "
            "transfer.csv --plot transfer.png. Every band is repeatable as one run: "
            "puckboard run SCENE --controller C --profile P --variation plausible --seed N "
            "plus the family's --set values (the rows of --out hold them)."
        ),
    )
    parser.add_argument(
        "scenario",
        nargs="+",
        metavar="SCENE",
        help="shipped scene names or .toml/.json scene files, one report block each",
    )
    add_controllers(parser)
    parser.add_argument(
        "--seeds",
        default=TRANSFER_SEEDS,
        metavar="A:B",
        help=f"seeds run on every model, a Python range (default: {TRANSFER_SEEDS})",
    )
    parser.add_argument(
        "--profile",
        action="append",
        default=[],
        metavar="NAME|FILE.toml",
        help="robot profile for every robot, shipped or a profile file (repeatable; default: "
        "each scene's)",
    )
    parser.add_argument(
        "--families",
        metavar="NAME,...",
        help="only these held-out families, comma-separated (default: all; a wrong name "
        "lists them)",
    )
    add_duration(parser)
    add_fixed_sets(
        parser,
        "e.g. layer.KeepClear.clearance=0.39, the numbers a tuning chose: every model's "
        "base, each family's changes on top",
    )
    add_where_to_run(parser)
    add_out(parser)
    parser.add_argument("--json", action="store_true", help="print the report as one JSON object")
    parser.add_argument(
        "--plot",
        type=Path,
        metavar="FILE",
        help="draw the families × controllers matrix and the radius bars (.png, .svg, .pdf; "
        "needs matplotlib)",
    )
    add_quiet(parser)
    parser.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    from ..sweep.signals import stop_on_terminate

    with stop_on_terminate():
        check_numbers(args)
        if args.plot is not None:
            check_plot_file(args.plot)
        return with_executor(args, _run)


def _run(args: argparse.Namespace, executor: SweepExecutor | None) -> int:
    from ..sweep.signals import interrupts_deferred
    from ..transfer import format_result, run_transfer_plan

    with interrupts_deferred():  # see cli/sweep.py: a Ctrl-C while importing waits
        plan, scenes = _plan(args)
        store = open_out(args)
    result = execute(
        args,
        executor,
        store,
        "transfer",
        lambda on: run_transfer_plan(plan, scenes, run_options(args, on, store, "transfer")),
    )
    if result is None:
        return 1
    # a report counts, times and ends as the sweeps it ran do (both are ExperimentRuns)
    result.wall_s = wall_time(args, result)
    if args.json:
        print(json.dumps(result.to_dict(), indent=2))
    else:
        print(format_result(result, stored=str(args.out) if store is not None else None))
    if args.plot is not None and result.episodes:
        from ..transfer import plot_transfer

        plot_transfer(result, args.plot)
        if not args.json:
            print(f"\nplot written to {args.plot}")
    return exit_status(args, result, stored=store is not None, command="transfer")


def _plan(args: argparse.Namespace) -> tuple[Any, dict[str, Any]]:
    """The report's points and every scene they run on, checked before anything runs
    (:func:`puckboard.transfer.plan_from_names`, as the Python API makes them)."""
    from ..errors import PuckboardError
    from ..transfer import plan_from_names

    names = None
    if args.families is not None:
        names = [n.strip() for n in args.families.split(",") if n.strip()]
        if not names:
            raise CliError("--families: name at least one family, e.g. --families noise")
    fixed = fixed_sets(
        args,
        why_one="a report judges one set of numbers; sweep --set compares them",
        robots="--profile's and each family's",
    )
    try:
        return plan_from_names(
            args.scenario,
            controllers=args.controller,
            profiles=args.profile,
            seeds=args.seeds,
            families=names,
            fixed=fixed,
        )
    except (PuckboardError, ValueError, OSError) as exc:
        raise CliError(str(exc)) from None
