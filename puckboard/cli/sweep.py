"""``puckboard sweep``: many episodes over controllers × seeds × parameters, summarised.

Runs on all local cores by default, or on an existing Dask cluster with ``--scheduler``.
See ``docs/sweeps.md`` for tuning a gain, grading a class and resuming long sweeps.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .errors import CliError
from .experiment_options import (
    add_duration,
    add_out,
    add_quiet,
    add_scene_and_controllers,
    add_where_to_run,
    check_numbers,
    execute,
    exit_status,
    open_out,
    run_options,
    scene_or_error,
    wall_time,
    with_executor,
)
from .parsing import add_variation_argument, settings_help

if TYPE_CHECKING:
    from ..scenario.scene import Scene
    from ..sweep.executors import SweepExecutor
    from ..sweep.plan import SweepPlan
    from ..sweep.run import SweepResult


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    parser = subparsers.add_parser(
        "sweep",
        help="run many episodes (seeds × parameters × controllers) and summarise success",
        description=(
            "Run every combination of controller × parameter values × seed with the embedded "
            "simulator, on all local cores or on a Dask cluster, and report each combination's "
            "success rate with a 95 % Wilson confidence interval, its failures by name, and "
            "mean progress and collisions. Several controllers are ranked. --out appends one "
            "row per episode to a CSV or Parquet file; re-running skips the rows already there."
        ),
        epilog=(
            f"parameters for --set: {settings_help()}, variation, "
            "layer.<LayerName>.<attribute>, profile.<path> (every robot's, SI or with a unit: "
            "profile.prox_radius.side=30mm,33mm; paths: puckboard profiles show), "
            "robot.<name>.profile.<path>. Example: "
            "puckboard sweep two-robot-pass --controller stock --controller improved "
            "--seeds 0:50 --set noise.proximity=0,0.05,0.1 --out runs.csv"
        ),
    )
    _add_what_to_run(parser)
    add_where_to_run(parser)
    _add_outputs(parser)
    parser.set_defaults(func=main)


def _add_what_to_run(parser: argparse.ArgumentParser) -> None:
    """The sweep's grid: scene, controllers, seeds, swept parameters."""
    add_scene_and_controllers(parser)
    parser.add_argument(
        "--controllers-dir",
        type=Path,
        metavar="DIR",
        help="grade every DIR/*.py defining make_controller(**params) (files starting with _ "
        "are skipped)",
    )
    parser.add_argument(
        "--seeds",
        default="0:10",
        metavar="A:B",
        help="seeds as a Python range, A included, B excluded (default: 0:10)",
    )
    parser.add_argument(
        "--set",
        dest="sets",
        action="append",
        default=[],
        metavar="PARAM=V1,V2,...",
        help="sweep a parameter over values (repeatable; see the list below)",
    )
    add_duration(parser)
    parser.add_argument(
        "--profile",
        metavar="NAME|FILE.toml",
        help="robot profile for every robot, shipped or a profile file (its base and its "
        "values become fixed parameters of every episode; default: the scene's; to compare "
        "profiles, --set robot.profile=epuck,epuck-vrep)",
    )
    add_variation_argument(parser, "each episode's seed from --seeds")


def _add_outputs(parser: argparse.ArgumentParser) -> None:
    """Where the rows, the summary and the plot go."""
    add_out(parser)
    parser.add_argument("--json", action="store_true", help="print the summary as one JSON object")
    parser.add_argument(
        "--plot",
        type=Path,
        metavar="FILE",
        help="plot success rate against a swept parameter (.png, .svg, .pdf; needs matplotlib)",
    )
    parser.add_argument(
        "--plot-param",
        metavar="PARAM",
        help="parameter for the plot's x axis (default: the first --set with several values)",
    )
    add_quiet(parser)


def main(args: argparse.Namespace) -> int:
    from ..sweep.signals import stop_on_terminate

    # SIGTERM stops the sweep as Ctrl-C does (finished rows kept, workers ended) instead
    # of killing this process on the spot.
    with stop_on_terminate():
        return _sweep(args)


def _sweep(args: argparse.Namespace) -> int:
    check_numbers(args)
    return with_executor(args, _run, episodes=_episode_count(args))


def _episode_count(args: argparse.Namespace) -> int | None:
    """How many episodes the sweep plans, known from the options alone (``None`` where
    it needs more: a folder of controllers, or options the plan will refuse)."""
    from ..sweep import PlanError, SweepPlan

    if args.controllers_dir is not None:
        return None
    try:
        plan = SweepPlan.from_specs(
            "count", controllers=args.controller, seeds=args.seeds, sets=args.sets
        )
    except (PlanError, ValueError):
        return None
    return len(plan)


def _run(args: argparse.Namespace, executor: SweepExecutor | None) -> int:
    from ..sweep import run_sweep
    from ..sweep.signals import interrupts_deferred

    # Ctrl-C here waits the moment the preparation takes and is raised after it: raised
    # inside one of the many modules it imports, Python 3.11 would end the process by
    # SIGINT after our one-line message (a KeyboardInterrupt within exec() of source
    # text, as dataclasses do, counts as unhandled even when caught).
    with interrupts_deferred():
        scene = scene_or_error(args.scenario)
        plan = _plan(args, scene)
        plot_param = _plot_param(args, plan)
        store = open_out(args)
    result = execute(
        args,
        executor,
        store,
        "sweep",
        lambda on: run_sweep(plan, scene, run_options(args, on, store, "sweep")),
    )
    if result is None:
        return 1
    _report(args, plan, result, stored=store is not None, plot_param=plot_param)
    return exit_status(args, result, stored=store is not None)


def _plan(args: argparse.Namespace, scene: Scene) -> SweepPlan:
    """The grid of episodes, checked before any runs: a bad controller spec or value is an
    error, as in 'run'; a graded submission that will fail is a warning ('error' episodes)."""
    from ..sweep import PlanError, SweepPlan, check_plan, controllers_in_dir

    controllers = list(args.controller)
    graded: list[str] = []  # submissions: a broken one must not stop the others
    if args.controllers_dir is not None:
        try:
            graded = controllers_in_dir(args.controllers_dir)
        except ValueError as exc:
            raise CliError(str(exc)) from exc
        controllers += graded
    fixed: dict[str, Any] = {} if args.duration is None else {"duration": args.duration}
    if args.profile is not None:
        if any(s.partition("=")[0].strip() == "robot.profile" for s in args.sets):
            raise CliError("give either --profile or --set robot.profile=..., not both")
        fixed.update(_profile_parameters(args.profile))
    if getattr(args, "variation_given", False):
        fixed["variation"] = args.variation
    try:
        plan = SweepPlan.from_specs(
            scene.name, controllers=controllers, seeds=args.seeds, sets=args.sets, fixed=fixed
        )
        warnings = check_plan(plan, scene, tolerate=graded)
    except PlanError as exc:
        raise CliError(str(exc)) from exc
    for warning in warnings:
        print(
            f"puckboard sweep: warning: {warning} (its episodes count as 'error')", file=sys.stderr
        )
    return plan


def _profile_parameters(ref: str) -> dict[str, Any]:
    """``--profile`` as fixed parameters: a shipped profile by name; a profile file as its
    base plus each value it sets, so every episode's identity holds the numbers it ran
    with and no worker needs the file."""
    from ..errors import PuckboardError
    from ..scenario.robot_profiles import scene_profile
    from ..sweep.plan import profile_parameters

    try:
        return profile_parameters(scene_profile(ref))
    except PuckboardError as exc:
        raise CliError(str(exc)) from None


def _plot_param(args: argparse.Namespace, plan: SweepPlan) -> str | None:
    if args.plot_param is not None and args.plot is None:
        raise CliError(
            "--plot-param chooses the x axis of --plot; add --plot FILE (.png, .svg, .pdf)"
        )
    plot_param: str | None = args.plot_param or (plan.swept[0] if plan.swept else None)
    if args.plot is not None:
        if plot_param is None:
            raise CliError("--plot needs a parameter swept over several values (--set PARAM=V1,V2)")
        if plot_param not in plan.grid and plot_param not in plan.fixed:
            raise CliError(f"--plot-param {plot_param!r} is not a parameter of this sweep")
    return plot_param


def _report(
    args: argparse.Namespace,
    plan: SweepPlan,
    result: SweepResult,
    *,
    stored: bool,
    plot_param: str | None,
) -> None:
    """The summary table (or JSON), the ranking of several controllers, and the plot."""
    from ..sweep.plan import written_values
    from ..sweep.summary import format_groups, format_ranking

    groups = result.groups()
    if args.json:
        print(json.dumps(result.to_dict(), indent=2))
    else:
        file = str(args.out) if stored else None
        print(f"{plan.scenario}: {result.episodes_text(file)}, {wall_time(args, result):.1f} s")
        print()
        print(format_groups(groups, written_values(args.sets)))
        if len(plan.controllers) > 1:
            print()
            print("ranking (all parameter values pooled):")
            print(format_ranking(result.ranking()))
    if args.plot is not None and plot_param is not None and groups:
        from ..sweep.plot import plot_success

        plot_success(groups, plot_param, args.plot, title=plan.scenario)
        if not args.json:
            print(f"\nplot written to {args.plot}")
