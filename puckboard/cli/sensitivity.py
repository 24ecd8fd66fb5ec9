"""``puckboard sensitivity``: which uncertain numbers of the robot move the success rate.

Two methods. ``one-at-a-time`` (the default): each uncertain field of each profile is set
to evenly spaced values across its plausible range, one field at a time, on every robot;
every value runs the same seeds, beside the shipped profile and plausible robots.
``joint``: plausible robots with every number drawn at once, one per seed; the same
episodes give the band and, binned by each drawn number, its curve and a ranking
(:mod:`puckboard.sensitivity.joint`). ``--from FILE`` recomputes a joint analysis from
stored rows. Runs on the sweep machinery: all local cores or a Dask cluster, ``--out``
rows to resume from, Ctrl-C keeps what ran. See ``docs/sweeps.md`` (sensitivity) and
``docs/profiles.md`` (the ranges).
"""

from __future__ import annotations

import argparse
import json
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

from ..sweep.defaults import JOINT_SEEDS, SENSITIVITY_SEEDS
from .checks import check_plot_file
from .errors import CliError
from .experiment_options import (
    add_duration,
    add_fixed_sets,
    add_out,
    add_quiet,
    add_scene_and_controllers,
    add_where_to_run,
    check_numbers,
    execute,
    exit_status,
    fixed_sets,
    open_out,
    run_options,
    scene_or_error,
    with_executor,
)
from .parsing import VariationName

if TYPE_CHECKING:
    from ..profile import RobotProfile
    from ..scenario.scene import Scene
    from ..sensitivity import SensitivityPlan
    from ..sensitivity.joint import JointPlan, JointResult
    from ..sweep.executors import SweepExecutor
    from ..sweep.store import ResultStore

R = TypeVar("R")  # what an analysis returns

DEFAULT_SEEDS = SENSITIVITY_SEEDS
METHODS = ("one-at-a-time", "joint")


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    parser = subparsers.add_parser(
        "sensitivity",
        help="vary each uncertain number of the robot across its range: which ones move the "
        "success rate",
        description=(
            "For each controller and profile, set each uncertain field of the profile "
            "(puckboard profiles show NAME lists them with their ranges and sources) to "
            "evenly spaced values across its plausible range, one field at a time, on every "
            "robot, and run the same seeds at each value. Reports the success rate with its "
            "95 % Wilson interval per field and value, the fields ranked by how far they move "
            "the rate (a tornado chart with --plot), and the rates of the shipped profile and "
            "of plausible robots (--variation plausible) on the same seeds. Runs on all local "
            "cores or a Dask cluster; --out keeps one row per episode, and the same command "
            "resumes from it. --method joint instead draws every number of every robot at "
            "once, one plausible robot pair per seed: the same episodes give the plausible "
            "robots' rate, each drawn number's binned curve and the numbers ranked, or say "
            "that nothing is clear at this many seeds; --from FILE recomputes that from the "
            "rows of FILE."
        ),
        epilog=(
            "Example: puckboard sensitivity two-robot-pass --controller improved --profile "
            "epuck --seeds 0:20 --plot sensitivity.png. Every value is repeatable as one run: "
            "puckboard run SCENE --profile P --set profile.FIELD=VALUE --seed N. Joint: "
            "puckboard sensitivity two-robot-pass --controller improved --profile epuck "
            "--method joint --seeds 0:300 --out joint.parquet; then puckboard sensitivity "
            "--from joint.parquet --plot joint.png."
        ),
    )
    add_scene_and_controllers(parser)
    parser.add_argument(
        "--method",
        choices=METHODS,
        default=None,
        help="one-at-a-time (default): each field across its range, the others as shipped; "
        "joint: plausible robots with every number drawn at once, each number's binned "
        "curve and a ranking from the same episodes (seeds default to "
        f"{JOINT_SEEDS})",
    )
    parser.add_argument(
        "--from",
        dest="source",
        type=Path,
        metavar="FILE",
        help="recompute a joint analysis from the rows of FILE (.csv or .parquet, written by "
        "--method joint --out, or sweep --variation plausible --out) without running an "
        "episode",
    )
    parser.add_argument(
        "--bins",
        type=int,
        default=None,
        metavar="N",
        help="joint method: equal-count bins per number (default: 4, quarters)",
    )
    parser.add_argument(
        "--profile",
        action="append",
        default=[],
        metavar="NAME|FILE.toml",
        help="robot profile for every robot, shipped or a profile file (repeatable; default: "
        "the scene's); a file's own numbers are measured, not varied",
    )
    parser.add_argument(
        "--fields",
        metavar="F,...",
        help="only these uncertain fields, comma-separated (e.g. prox_radius.side,ir_gain; "
        "default: every uncertain field of each profile)",
    )
    parser.add_argument(
        "--seeds",
        default=None,
        metavar="A:B",
        help=f"seeds run at every value, a Python range (default: {DEFAULT_SEEDS}; with "
        f"--method joint, one plausible robot each, default {JOINT_SEEDS})",
    )
    parser.add_argument(
        "--values",
        type=int,
        default=None,
        metavar="N",
        help="evenly spaced values per field, both ends of its range included (default: 7, "
        "at most 100); the shipped value is a point of its own",
    )
    add_duration(parser)
    add_fixed_sets(
        parser,
        "e.g. control.period=0.1, noise.ground=0.05; the robots' numbers come from --profile",
    )
    parser.add_argument(
        "--variation",
        action=VariationName,
        default=None,
        metavar="NAME",
        help="plausible: at each value draw every other number of each robot within its range "
        "(the field's effect on robots that differ in everything else); reality-gap: the same, "
        "in conditions drawn within sourced ranges too; default none: the "
        "other numbers keep the profile's values. The plausible robots' own rate is reported "
        "either way",
    )
    add_where_to_run(parser)
    add_out(parser)
    parser.add_argument("--json", action="store_true", help="print the results as one JSON object")
    parser.add_argument(
        "--plot",
        type=Path,
        metavar="FILE",
        help="draw the tornado chart and one panel per field (.png, .svg, .pdf; needs matplotlib)",
    )
    add_quiet(parser)
    parser.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    from ..sweep.signals import stop_on_terminate

    with stop_on_terminate():
        return _sensitivity(args)


def _sensitivity(args: argparse.Namespace) -> int:
    from ..sensitivity.joint.estimate import DEFAULT_BINS
    from ..sensitivity.one_at_a_time.plan import DEFAULT_VALUES

    check_numbers(args)
    _refuse_unused(args)
    args.values = DEFAULT_VALUES if args.values is None else args.values
    args.bins = DEFAULT_BINS if args.bins is None else args.bins
    args.variation = args.variation or "none"
    if args.values < 1:
        raise CliError(f"--values must be at least 1, got {args.values}")
    if args.bins < 2:
        raise CliError(f"--bins must be at least 2, got {args.bins}")
    if args.plot is not None:
        check_plot_file(args.plot)
    if args.source is not None:
        return _from_file(args)
    args.method = args.method or "one-at-a-time"
    if args.seeds is None:
        args.seeds = JOINT_SEEDS if args.method == "joint" else DEFAULT_SEEDS
    return with_executor(args, _run_joint if args.method == "joint" else _run)


#: Options that say how episodes run, as their ``args`` names and flags: ``--from`` runs
#: none, so each one given with it would be silently ignored.
_RUN_ONLY = (
    ("controller", "--controller"), ("seeds", "--seeds"), ("profile", "--profile"),
    ("fields", "--fields"), ("values", "--values"), ("variation", "--variation"),
    ("duration", "--duration"), ("out", "--out"), ("workers", "--workers"),
    ("scheduler", "--scheduler"), ("episode_timeout", "--episode-timeout"),
    ("batch_size", "--batch-size"), ("sets", "--set"),
)  # fmt: skip


def _refuse_unused(args: argparse.Namespace) -> None:
    """Refuse, in one line, an option the chosen method would not use: given and silently
    ignored, it would leave the user believing it took effect."""
    if args.source is not None:
        if args.method == "one-at-a-time":
            raise CliError(
                "--from recomputes a joint analysis; drop --method one-at-a-time (a "
                "one-at-a-time analysis resumes from its --out file by running it again)"
            )
        given = [flag for name, flag in _RUN_ONLY if getattr(args, name) not in (None, [])]
        if given:
            raise CliError(
                f"--from analyses the rows {str(args.source)!r} holds and runs no episode: "
                f"drop {', '.join(given)} (to run other controllers or seeds, run --method "
                "joint with them and --out FILE)"
            )
        return
    if args.method == "joint":
        why = {
            "fields": "the joint method draws every number",
            "values": "the joint method draws every number; its curves have --bins bins",
            "variation": "the joint method's robots are always plausible (every number drawn)",
        }
        for name, reason in why.items():
            if getattr(args, name) is not None:
                raise CliError(f"--{name} is for --method one-at-a-time; {reason}")
    elif args.bins is not None:
        raise CliError(
            "--bins is for --method joint and --from; one at a time, each field's curve has "
            "--values values"
        )


def _run(args: argparse.Namespace, executor: SweepExecutor | None) -> int:
    from ..sensitivity import format_result, run_sensitivity
    from ..sweep.signals import interrupts_deferred

    with interrupts_deferred():  # see cli/sweep.py: a Ctrl-C while importing waits
        scene = scene_or_error(args.scenario)
        plan = _plan(args, scene)
        store = open_out(args)
    result = _execute(args, executor, store, run_sensitivity, plan, scene)
    if result is None:
        return 1
    if args.json:
        print(json.dumps(result.to_dict(), indent=2))
    else:
        print(format_result(result, stored=str(args.out) if store is not None else None))
    if args.plot is not None and result.sweep.outcomes:
        from ..sensitivity import plot_sensitivity

        plot_sensitivity(result, args.plot)
        if not args.json:
            print(f"\nplot written to {args.plot}")
    return exit_status(args, result.sweep, stored=store is not None, command="sensitivity")


def _execute(
    args: argparse.Namespace,
    executor: SweepExecutor | None,
    store: ResultStore | None,
    analysis: Callable[..., R],
    plan: SensitivityPlan | JointPlan,
    scene: Scene,
) -> R | None:
    """Run ``analysis`` (one-at-a-time's or the joint one) on the executor with the
    options both methods share; ``None`` when it was stopped (see ``execute``)."""

    return execute(
        args,
        executor,
        store,
        "sensitivity",
        lambda on: analysis(plan, scene, run_options(args, on, store, "sensitivity")),
    )


def _profiles(args: argparse.Namespace, scene: Scene) -> list[str | RobotProfile]:
    """``--profile`` each as a shipped name or a profile, else the scene's one profile."""
    from ..errors import PuckboardError
    from ..scenario.robot_profiles import scene_profile

    if args.profile:
        try:
            return [scene_profile(ref) for ref in args.profile]
        except PuckboardError as exc:
            raise CliError(str(exc)) from None
    own = {json.dumps(_profile_id(r.profile)) for r in scene.robots}
    if len(own) != 1:
        raise CliError(
            f"the robots of {scene.name} have different profiles; name the one to analyse "
            "with --profile NAME (repeatable)"
        )
    return [scene.robots[0].profile]


def _profile_id(profile: str | RobotProfile) -> str | list[Any]:
    return profile if isinstance(profile, str) else [profile.name, list(profile.overrides)]


def _plan(args: argparse.Namespace, scene: Scene) -> SensitivityPlan:
    """The analysis's points, checked before any runs as a sweep's are."""
    from ..errors import PuckboardError
    from ..sensitivity import sensitivity_plan
    from ..sweep import SCENE_CONTROLLERS, PlanError, check_plan
    from ..sweep.plan import parse_seeds

    fields = None
    if args.fields is not None:
        fields = [f.strip() for f in args.fields.split(",") if f.strip()]
        if not fields:
            raise CliError("--fields: name at least one field, e.g. --fields prox_radius.side")
    fixed = _fixed(args)
    try:
        plan = sensitivity_plan(
            scene.name,
            profiles=_profiles(args, scene),
            controllers=args.controller or [SCENE_CONTROLLERS],
            seeds=parse_seeds(args.seeds),
            fields=fields,
            values=args.values,
            fixed=fixed,
            variation=args.variation,
        )
        check_plan(plan.sweep, scene)
    except (PlanError, PuckboardError) as exc:
        raise CliError(str(exc)) from exc
    return plan


def _fixed(args: argparse.Namespace) -> dict[str, Any]:
    """The parameters every episode of the analysis shares: ``--duration`` and ``--set``."""
    return fixed_sets(args, why_one="the analysis varies the robots")


def _run_joint(args: argparse.Namespace, executor: SweepExecutor | None) -> int:
    from ..errors import PuckboardError
    from ..sensitivity.joint import joint_plan, run_joint
    from ..sweep import SCENE_CONTROLLERS, PlanError, check_plan
    from ..sweep.plan import parse_seeds
    from ..sweep.signals import interrupts_deferred

    with interrupts_deferred():  # see cli/sweep.py: a Ctrl-C while importing waits
        _needs_statsmodels()
        scene = scene_or_error(args.scenario)
        try:
            plan = joint_plan(
                scene.name,
                profiles=_profiles(args, scene),
                controllers=args.controller or [SCENE_CONTROLLERS],
                seeds=parse_seeds(args.seeds),
                fixed=_fixed(args),
                bins=args.bins,
            )
            check_plan(plan.sweep, scene)
        except (PlanError, PuckboardError) as exc:
            raise CliError(str(exc)) from exc
        store = open_out(args)
    result = _execute(args, executor, store, run_joint, plan, scene)
    if result is None:
        return 1
    assert result.sweep is not None  # run, not read --from: it has its sweep
    _show_joint(args, result, stored=str(args.out) if store is not None else None)
    return exit_status(args, result.sweep, stored=store is not None, command="sensitivity")


def _needs_statsmodels() -> None:
    try:
        import statsmodels  # noqa: F401
    except ImportError:
        raise CliError(
            "--method joint needs statsmodels: pip install 'puckboard[analysis]'"
        ) from None


def _from_file(args: argparse.Namespace) -> int:
    """``--from FILE``: the joint analysis of the plausible robots' rows in FILE."""
    from ..sensitivity.joint import from_rows
    from ..sweep import PlanError, open_store

    _needs_statsmodels()
    if not args.source.is_file():
        raise CliError(f"--from {str(args.source)!r}: no such file")
    try:
        store = open_store(args.source)
    except ValueError as exc:  # its name: the message starts with it
        raise CliError(f"--from {exc}") from None
    try:
        with store:
            rows = store.rows()
        result = from_rows(rows, args.bins)
    except (PlanError, ValueError, KeyError, OSError, ImportError) as exc:
        raise CliError(f"--from {str(args.source)!r}: {exc}") from None
    _show_joint(args, result, stored=None)
    return 0


def _show_joint(args: argparse.Namespace, result: JointResult, stored: str | None) -> None:
    from ..sensitivity.joint import format_joint

    if args.json:
        print(json.dumps(result.to_dict(), indent=2))
    else:
        print(format_joint(result, stored=stored))
    if args.plot is not None and result.analyses:
        from ..sensitivity.joint import plot_joint

        plot_joint(result, args.plot)
        if not args.json:
            print(f"\nplot written to {args.plot}")
