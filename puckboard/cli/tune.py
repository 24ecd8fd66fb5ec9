"""``puckboard tune``: search a controller's numbers for the worst robot, not the average.

Each ``--param PATH=LOW:HIGH[:int][:log]`` is a range Optuna's seeded TPE sampler draws
from (``PATH=A,B,...``: a choice, for a setting that is true/false or a word); each
trial runs the design seeds (``--seeds``) on every scene × profile and is scored by its
worst cell, then the mean, then progress; hopeless trials are pruned after the first
rounds. ``--study FILE`` keeps every finished trial (Ctrl-C keeps them, the same
command resumes). The best parameters are run again on ``--validate`` seeds no trial
saw. See ``docs/sweeps.md`` (tuning).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..sweep.defaults import TUNE_TRIALS
from .errors import CliError, missing_extra, user_code_error
from .experiment_options import (
    add_duration,
    add_where_to_run,
    check_numbers,
    execute,
    scene_or_error,
    with_executor,
)
from .parsing import add_variation_argument

if TYPE_CHECKING:
    from collections.abc import Sequence

    from ..sweep.executors import SweepExecutor
    from ..tune import TuneResult, TuneSpec
    from ..tune.run import TrialEvent
    from ..tune.space import Choice, Param

DEFAULT_TRIALS = TUNE_TRIALS


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    parser = subparsers.add_parser(
        "tune",
        help="search a controller's parameters for the best worst-case success rate",
        description=(
            "Search ranges of a controller's parameters with Optuna (seeded TPE sampler, "
            "median pruner). Every trial runs the design seeds on each scene × profile (a "
            "cell) and is scored by its worst cell's success rate, ties broken by the mean "
            "rate and then by progress. The best parameters are then run on the validation "
            "seeds, which no trial used, and reported per cell with 95 % Wilson intervals. "
            "--study FILE keeps every finished trial; the same command resumes it."
        ),
        epilog=(
            "PATH is a keyword of the controller's factory (speed) or a layer's attribute "
            "(layer.<LayerName>.<attribute>, as for sweep --set). Ranges: LOW:HIGH (a real "
            "number), LOW:HIGH:int (a whole number), LOW:HIGH:log (drawn on a log scale), "
            "LOW:HIGH:int:log; a setting that is true/false or a word takes its choices instead: "
            "layer.LineFollow.recovery=true,false. Example: puckboard tune two-robot-pass "
            "--controller improved "
            "--param layer.LineFollow.inner_factor=0.1:0.9 --set robot.profile=epuck,epuck-vrep "
            "--variation plausible --seeds 0:40 --validate 40:140 --study tune.journal"
        ),
    )
    parser.add_argument(
        "scenes", nargs="+", metavar="SCENE", help="shipped scene names or scene files"
    )
    parser.add_argument(
        "--controller",
        required=True,
        metavar="SPEC",
        help="controller for every robot: stock, improved, robust, MODULE:FACTORY or "
        "FILE.py:FACTORY",
    )
    parser.add_argument(
        "--param", dest="params", action="append", required=True,
        metavar="PATH=LOW:HIGH[:int][:log]",
        help="a parameter and its range, or PATH=A,B,... its choices (repeatable)",
    )  # fmt: skip
    parser.add_argument(
        "--profile", dest="profiles", action="append", default=[], metavar="NAME",
        help="robot profile of every robot (repeatable: each is a cell; default: the scene's)",
    )  # fmt: skip
    parser.add_argument(
        "--set", dest="sets", action="append", default=[], metavar="PARAM=V",
        help="a fixed episode parameter, as for sweep --set; robot.profile=A,B makes cells",
    )  # fmt: skip
    add_variation_argument(parser)
    parser.add_argument(
        "--seeds", required=True, metavar="A:B", help="design seeds the trials are scored on"
    )
    parser.add_argument(
        "--validate", required=True, metavar="C:D",
        help="validation seeds for the best parameters; must not overlap --seeds",
    )  # fmt: skip
    parser.add_argument(
        "--trials", type=int, default=DEFAULT_TRIALS, metavar="N",
        help=f"finished trials wanted in the study (default {DEFAULT_TRIALS}); a resumed "
        "study runs only the rest",
    )  # fmt: skip
    parser.add_argument(
        "--rounds", type=int, default=None, metavar="N",
        help="rounds the design seeds are run in; a trial may be pruned after each but the "
        "first (default 4, or one per seed when there are fewer)",
    )  # fmt: skip
    parser.add_argument(
        "--sampler-seed", type=int, default=0, metavar="N",
        help="seed of the sampler: the same command and seed draw the same trials (default 0)",
    )  # fmt: skip
    parser.add_argument(
        "--study", type=Path, metavar="FILE",
        help="keep the study in FILE (an Optuna journal); the same command resumes it",
    )  # fmt: skip
    add_duration(parser)
    add_where_to_run(parser)
    parser.add_argument("--json", action="store_true", help="print the results as one JSON object")
    parser.add_argument(
        "--plot", type=Path, metavar="FILE",
        help="draw the optimisation history and the parameters' importances (.png, .svg, .pdf)",
    )  # fmt: skip
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress lines")
    parser.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    from ..sweep.signals import stop_on_terminate

    with stop_on_terminate():
        return _tune(args)


def _tune(args: argparse.Namespace) -> int:
    check_numbers(args)
    for flag, value, least in (("--trials", args.trials, 1), ("--rounds", args.rounds, 1)):
        if value is not None and value < least:
            raise CliError(f"{flag} must be at least {least}, got {value}")
    if not 0 <= args.sampler_seed < 2**32:  # what numpy, under Optuna's sampler, takes
        raise CliError(
            f"--sampler-seed must be a whole number from 0 to 2**32 - 1, got {args.sampler_seed}"
        )
    try:
        import optuna  # noqa: F401
    except ImportError as exc:
        raise missing_extra(exc, "puckboard tune") from None
    if args.plot is not None:
        from .checks import check_plot_file

        check_plot_file(args.plot)
    if args.study is not None:
        from .checks import check_writable

        check_writable(args.study, "--study")
    return with_executor(args, _run)


def _spec(args: argparse.Namespace) -> TuneSpec:
    """The study's command, checked before any runs: parameters against the controller,
    seeds, profiles and fixed settings against the scenes as a sweep checks them."""
    from ..errors import PuckboardError
    from ..sweep import PlanError, SweepPlan, check_plan
    from ..sweep.plan import parse_seeds, parse_set
    from ..tune import SpaceError, TuneSpec, parse_param
    from ..tune.run import DEFAULT_ROUNDS

    scenes = tuple(scene_or_error(ref) for ref in args.scenes)
    if len({s.name for s in scenes}) != len(scenes):
        raise CliError("a scene is named twice; give each scene once")
    try:
        params = tuple(parse_param(text) for text in args.params)
        _check_space(params, args.controller)
        fixed: dict[str, Any] = {} if args.duration is None else {"duration": args.duration}
        if getattr(args, "variation_given", False):
            fixed["variation"] = args.variation
        profiles = tuple(args.profiles)
        for text in args.sets:
            name, values = parse_set(text)
            if name == "robot.profile":
                if profiles:
                    raise CliError("give either --profile or --set robot.profile=..., not both")
                profiles = tuple(str(v) for v in values)
            elif len(values) > 1 or name in fixed:
                raise CliError(f"--set {name}: give one value (tune moves only --param ranges)")
            else:
                fixed[name] = values[0]
        seeds = parse_seeds(args.seeds)
        if args.rounds is not None and args.rounds > len(seeds):
            raise CliError(
                f"--rounds {args.rounds} is more than the {len(seeds)} design seeds of --seeds "
                f"{args.seeds}: each round needs a seed; give --rounds {len(seeds)} or fewer, "
                "or more seeds"
            )
        spec = TuneSpec(
            scenes=scenes,
            controller=args.controller,
            params=params,
            seeds=seeds,
            validate=_validate_seeds(args.validate),
            profiles=profiles,
            fixed=fixed,
            rounds=DEFAULT_ROUNDS if args.rounds is None else args.rounds,
            sampler_seed=args.sampler_seed,
        )
        count = max(len(p.ends) for p in params)  # both ends of a range, every choice
        ends = [{p.name: p.ends[min(i, len(p.ends) - 1)] for p in params} for i in range(count)]
        for scene in scenes:  # as a sweep's values are checked
            check_plan(
                SweepPlan(
                    scenario=scene.name, controllers=(args.controller,), seeds=range(1),
                    grid={"robot.profile": profiles} if profiles else {}, fixed=fixed,
                    points=tuple(ends),
                ),
                scene,
            )  # fmt: skip
    except (SpaceError, PlanError, PuckboardError, ValueError) as exc:
        raise CliError(str(exc)) from None
    return spec


def _check_space(params: Sequence[Param | Choice], controller: str) -> None:
    """:func:`~puckboard.tune.check_space`; an error in the user's own controller file
    shown as Python shows it, as ``run`` does."""
    from ..tune import SpaceError, check_space

    try:
        check_space(params, controller)
    except (SpaceError, ValueError):
        raise
    except Exception as exc:  # the user's factory may raise anything
        error = user_code_error(exc, f"the controller {controller!r}")
        if error is None:
            raise
        raise error from None


def _validate_seeds(text: str) -> range:
    from ..sweep.plan import PlanError, parse_seeds

    try:
        return parse_seeds(text)
    except PlanError as exc:
        raise PlanError(str(exc).replace("--seeds", "--validate", 1)) from None


def _run(args: argparse.Namespace, executor: SweepExecutor | None) -> int:
    from ..sweep.progress import make_progress
    from ..sweep.signals import interrupts_deferred
    from ..tune import Interrupted, StudyMismatch, run_tune

    with interrupts_deferred():  # see cli/sweep.py: a Ctrl-C while importing waits
        spec = _spec(args)
    try:
        result = execute(
            args,
            executor,
            None,
            "tune",
            lambda on: run_tune(
                spec,
                args.trials,
                executor=on,
                study_path=args.study,
                episode_timeout=args.episode_timeout,
                on_trial=None if args.quiet else _show_trial,
                progress=make_progress(not args.quiet, label="tune validation"),
            ),
        )
    except StudyMismatch as exc:
        raise CliError(str(exc)) from None
    except KeyboardInterrupt as exc:
        terminated = isinstance(exc, Interrupted) and exc.terminated
        kept = (
            f"; finished trials are kept in {args.study}: run the same command again to resume"
            if args.study is not None
            else " (no --study: nothing kept)"
        )
        print(
            f"puckboard tune: {'terminated' if terminated else 'interrupted'}{kept}",
            file=sys.stderr,
        )
        return 143 if terminated else 130
    if result is None:
        return 1
    _report(args, result)
    return 0


def _show_trial(event: TrialEvent) -> None:
    from ..sweep.progress import _clock

    state = "pruned" if event.pruned else "complete"
    best = (
        f"best so far: trial {event.best_number}, worst cell {100 * event.best_worst:.1f} %"
        if event.best_number is not None and event.best_worst is not None  # set together
        else "no trial complete yet"
    )
    left = "?" if event.seconds_left is None else _clock(event.seconds_left)
    print(
        f"tune: trial {event.number} {state}; {event.finished}/{event.total} trials, {best}, "
        f"left ~{left}",
        file=sys.stderr,
        flush=True,
    )


def _report(args: argparse.Namespace, result: TuneResult) -> None:
    from ..tune import format_result, result_dict

    if args.json:
        print(json.dumps(result_dict(result), indent=2))
        for cell in result.overfit():
            print(
                f"puckboard tune: warning: {cell.label}: validation is below design beyond "
                "both intervals (over-fitted to the design seeds)",
                file=sys.stderr,
            )
    else:
        print(format_result(result, stored=str(args.study) if args.study else None))
    if args.plot is not None and result.trials:
        from ..tune import plot_tune

        plot_tune(result, args.plot)
        if not args.json:
            print(f"\nplot written to {args.plot}")
