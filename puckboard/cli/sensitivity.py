"""``puckboard sensitivity``: which uncertain numbers of the robot move the success rate.

Each uncertain field of each profile is set to evenly spaced values across its
plausible range, one field at a time, on every robot; every value runs the same seeds,
beside the shipped profile and plausible robots. Runs on the sweep machinery: all local
cores or a Dask cluster, ``--out`` rows to resume from, Ctrl-C keeps what ran.
See ``docs/sweeps.md`` (sensitivity) and ``docs/profiles.md`` (the ranges).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from .common import CliError
from .sweep import (
    add_duration,
    add_scene_and_controllers,
    add_where_to_run,
    check_numbers,
    execute,
    exit_status,
    open_out,
    scene_or_error,
    with_executor,
)

#: Seeds per value unless asked otherwise: a whole profile (the physical e-puck's 16
#: fields × 7 values, about 2,000 episodes) of one controller in about six minutes on two
#: cores, at the two-robot pass's measured 6 episodes/s (docs/simulator.md).
DEFAULT_SEEDS = "0:20"


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
            "resumes from it."
        ),
        epilog=(
            "Example: puckboard sensitivity two-robot-pass --controller improved --profile "
            "epuck --seeds 0:20 --plot sensitivity.png. Every value is repeatable as one run: "
            "puckboard run SCENE --profile P --set profile.FIELD=VALUE --seed N."
        ),
    )
    add_scene_and_controllers(parser)
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
        default=DEFAULT_SEEDS,
        metavar="A:B",
        help=f"seeds run at every value, a Python range (default: {DEFAULT_SEEDS})",
    )
    parser.add_argument(
        "--values",
        type=int,
        default=7,
        metavar="N",
        help="evenly spaced values per field, both ends of its range included (default: 7); "
        "the shipped value is a point of its own",
    )
    add_duration(parser)
    parser.add_argument(
        "--variation",
        choices=("none", "plausible"),
        default="none",
        help="plausible: at each value draw every other number of each robot within its range "
        "(the field's effect on robots that differ in everything else); default none: the "
        "other numbers keep the profile's values. The plausible robots' own rate is reported "
        "either way",
    )
    add_where_to_run(parser)
    parser.add_argument(
        "--out",
        type=Path,
        metavar="FILE",
        help="append one row per episode to FILE (.csv or .parquet); re-runs skip rows already "
        "there",
    )
    parser.add_argument("--json", action="store_true", help="print the results as one JSON object")
    parser.add_argument(
        "--plot",
        type=Path,
        metavar="FILE",
        help="draw the tornado chart and one panel per field (.png, .svg, .pdf; needs matplotlib)",
    )
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress display")
    parser.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    from ..sweep.signals import stop_on_terminate

    with stop_on_terminate():
        return _sensitivity(args)


def _sensitivity(args: argparse.Namespace) -> int:
    check_numbers(args)
    if args.values < 1:
        raise CliError(f"--values must be at least 1, got {args.values}")
    if args.plot is not None:
        _check_plot(args.plot)
    return with_executor(args, _run)


def _check_plot(path: Path) -> None:
    if path.suffix.lower() not in (".png", ".svg", ".pdf"):
        raise CliError(f"--plot {str(path)!r}: use a .png, .svg or .pdf file name")
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise CliError("--plot needs matplotlib: pip install 'puckboard[viz]'") from None


def _run(args: argparse.Namespace, executor: Any) -> int:
    from ..sensitivity import format_result, run_sensitivity
    from ..sweep import make_progress
    from ..sweep.signals import interrupts_deferred

    with interrupts_deferred():  # see cli/sweep.py: a Ctrl-C while importing waits
        scene = scene_or_error(args.scenario)
        plan = _plan(args, scene)
        store = open_out(args)
    result = execute(
        args,
        executor,
        store,
        "sensitivity",
        lambda on: run_sensitivity(
            plan,
            scene,
            executor=on,
            store=store,
            batch_size=args.batch_size,
            progress=make_progress(enabled=not args.quiet, label="sensitivity"),
            episode_timeout=args.episode_timeout,
        ),
    )
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


def _profiles(args: argparse.Namespace, scene: Any) -> list[Any]:
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


def _profile_id(profile: Any) -> Any:
    return profile if isinstance(profile, str) else [profile.name, list(profile.overrides)]


def _plan(args: argparse.Namespace, scene: Any) -> Any:
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
    fixed = {} if args.duration is None else {"duration": args.duration}
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
