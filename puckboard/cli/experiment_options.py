"""The options and steps every experiment command shares (``sweep``, ``sensitivity``,
``tune``): what is judged, where the episodes run, the checks made before any runs, the
run itself on local workers or a Dask cluster, and how it ended.

Each experiment command is a plan of episodes on the sweep machinery
(:mod:`puckboard.sweep`); this module is how a command offers that machinery on its
command line, so the same flag reads, is checked and fails the same way in each. A new
experiment command builds its parser from the ``add_*`` functions, checks its numbers
with :func:`check_numbers`, and runs through :func:`with_executor` and :func:`execute`;
:func:`exit_status` says how it ended (0; 130 after Ctrl-C; 143 after SIGTERM).
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

from ..sweep.defaults import DEFAULT_SCENARIO
from .checks import check_seconds, check_writable
from .errors import CliError

if TYPE_CHECKING:
    from ..scenario.scene import Scene
    from ..sweep.executors import SweepExecutor
    from ..sweep.experiment import ExperimentRun
    from ..sweep.options import RunOptions
    from ..sweep.store import ResultStore

__all__ = [
    "add_controllers",
    "add_duration",
    "add_fixed_sets",
    "add_out",
    "add_quiet",
    "add_scene_and_controllers",
    "add_where_to_run",
    "check_numbers",
    "dask_executor",
    "execute",
    "exit_status",
    "fixed_sets",
    "open_out",
    "run_options",
    "scene_or_error",
    "wall_time",
    "with_executor",
]

T = TypeVar("T")


def add_scene_and_controllers(parser: argparse.ArgumentParser) -> None:
    """What is judged: the scene, and the controllers compared on it."""
    parser.add_argument(
        "scenario",
        nargs="?",
        default=DEFAULT_SCENARIO,
        metavar="SCENARIO | SCENE_FILE",
        help=f"shipped scene name or a .toml/.json scene file (default: {DEFAULT_SCENARIO})",
    )
    add_controllers(parser)


def add_controllers(parser: argparse.ArgumentParser) -> None:
    """The controllers compared (``--controller``, repeatable)."""
    parser.add_argument(
        "--controller",
        action="append",
        default=[],
        metavar="SPEC",
        help="controller for every robot: stock, improved, robust, MODULE:FACTORY or "
        "FILE.py:FACTORY (repeatable; default: each robot's controller from the scene)",
    )


def add_duration(parser: argparse.ArgumentParser) -> None:
    """Every episode's simulated length (checked by :func:`check_numbers`)."""
    parser.add_argument(
        "--duration",
        type=float,
        metavar="S",
        help="simulated seconds per episode (default: scene's)",
    )


def add_fixed_sets(parser: argparse.ArgumentParser, example: str) -> None:
    """``--set PARAM=V`` (repeatable): one value each, every episode's (read by
    :func:`fixed_sets`); ``example`` ends the help (what the command's own sets are for)."""
    parser.add_argument(
        "--set",
        dest="sets",
        action="append",
        default=[],
        metavar="PARAM=V",
        help=f"a fixed episode parameter, one value, as for sweep --set (repeatable; {example})",
    )


def fixed_sets(
    args: argparse.Namespace, *, why_one: str, robots: str = "--profile's and --variation's"
) -> dict[str, Any]:
    """``--duration`` and each ``--set PARAM=V`` as the parameters every episode shares.

    The robots are the command's ``--profile`` and variation to say (``robots`` names
    them; a profile file sets their numbers), so ``profile.*``, ``robot.*`` and
    ``variation`` are refused; so is a second value (``why_one`` says why the command
    takes one) and a parameter given twice.
    """
    from ..sweep.plan import PlanError, parse_set

    fixed: dict[str, Any] = {} if args.duration is None else {"duration": args.duration}
    for text in args.sets:
        try:
            name, values = parse_set(text)
        except PlanError as exc:
            raise CliError(str(exc)) from None
        if name.startswith(("profile.", "robot.")) or name == "variation":
            raise CliError(
                f"--set {name}: the robots are {robots} to say; "
                "--set takes the other parameters (control.*, noise.*, dt, layer.* ...)"
            )
        if len(values) != 1:
            raise CliError(f"--set {name}: give one value ({why_one})")
        if name in fixed:
            flag = "--duration and --set duration" if name == "duration" else f"--set {name}"
            raise CliError(f"{flag}: given twice; give it once")
        fixed[name] = values[0]
    return fixed


def add_where_to_run(parser: argparse.ArgumentParser) -> None:
    """Executors and their limits: local processes or a Dask cluster, batches, timeouts."""
    where = parser.add_mutually_exclusive_group()
    where.add_argument(
        "--workers", type=int, metavar="N", help="local worker processes (default: all CPUs)"
    )
    where.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="run on an existing Dask cluster, e.g. tcp://10.0.0.5:8786 (needs puckboard[dask])",
    )
    parser.add_argument(
        "--episode-timeout",
        type=float,
        metavar="S",
        help="wall-clock seconds after which an episode is stopped and counted as 'error' "
        "of kind 'timeout': the process running it is killed and replaced, which stops any "
        "layer (a busy loop, time.sleep, a call blocked in C); only on a Dask cluster whose "
        "workers may not start processes (docs/sweeps.md) is the episode interrupted from "
        "within instead, which stops a layer running Python code but not one blocked in C "
        "(default: no limit)",
    )
    parser.add_argument(
        "--batch-size",
        type=int,
        metavar="N",
        help="episodes per task (default: automatic, at most 8)",
    )


def add_out(parser: argparse.ArgumentParser) -> None:
    """``--out FILE``: one row per episode (read by :func:`open_out`); the same command
    resumes from it."""
    parser.add_argument(
        "--out",
        type=Path,
        metavar="FILE",
        help="append one row per episode to FILE (.csv, or .parquet with puckboard[dask]); "
        "re-runs skip rows already there",
    )


def add_quiet(parser: argparse.ArgumentParser) -> None:
    """``-q``: no progress display (the result still goes to stdout)."""
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress display")


def check_numbers(args: argparse.Namespace) -> None:
    check_seconds(args.duration)
    if args.batch_size is not None and args.batch_size < 1:
        raise CliError(f"--batch-size must be at least 1, got {args.batch_size}")
    if args.episode_timeout is not None and not args.episode_timeout > 0:
        raise CliError(f"--episode-timeout must be positive seconds, got {args.episode_timeout}")
    if args.workers is not None and args.workers < 1:
        raise CliError(f"--workers must be at least 1, got {args.workers}")
    # outputs of sweep and sensitivity alike: a plot refused after the whole run loses it
    for flag in ("--out", "--plot"):
        path = getattr(args, flag[2:], None)
        if path is not None:
            check_writable(path, flag)


def scene_or_error(ref: str) -> Scene:
    """The scene ``ref`` names (a shipped name or a scene file), or its one-line error."""
    from ..scenario.scenefile import load_scene

    try:
        return load_scene(ref)
    except (ValueError, OSError) as exc:
        raise CliError(str(exc)) from exc


def open_out(args: argparse.Namespace) -> ResultStore | None:
    """The ``--out`` file's store (``None`` without ``--out``); a file that cannot be
    used is one line."""
    from ..sweep import open_store

    try:
        return open_store(args.out) if args.out is not None else None
    except ValueError as exc:  # the file's name or contents: the flag that named it
        raise CliError(f"--out {exc}") from exc
    except (ImportError, OSError) as exc:
        raise CliError(f"--out {str(args.out)!r}: {exc}") from exc


def with_executor(
    args: argparse.Namespace,
    run: Callable[[argparse.Namespace, SweepExecutor | None], int],
    *,
    episodes: int | None = None,
) -> int:
    """``run(args, executor)`` with local workers, or with ``None`` for ``--scheduler``
    (``run`` connects to the cluster only once its plan is known to be good).

    No more workers start than there are ``episodes`` (when known): each is a process
    with its own interpreter and imports, and one with no episode only costs start-up.
    ``--workers`` above the CPUs is allowed (a machine may be shared) with a warning.
    """
    from ..sweep import LocalExecutor
    from ..sweep.executors import available_cpus

    args.started = time.perf_counter()  # the wall time reported counts the start-up too
    if args.scheduler:
        return run(args, None)
    workers = args.workers
    if workers is not None:
        cpus = available_cpus()
        if episodes is not None:
            workers = max(1, min(workers, episodes))
        if workers > cpus:
            print(
                f"puckboard {args.command}: warning: --workers {workers} is more than this "
                f"machine's {cpus} CPUs; the workers share them, which starts slower and runs "
                "no faster",
                file=sys.stderr,
            )
    # Local workers start up (an interpreter and the imports each) while this process
    # loads the scene, checks the plan and reads --out; on bad input they are ended.
    local = LocalExecutor(workers)
    try:
        local.start()
        return run(args, local)
    except BaseException:
        local.cancel()
        raise
    finally:
        local.close()


def dask_executor(args: argparse.Namespace) -> SweepExecutor:
    from ..sweep import DaskExecutor

    try:
        return DaskExecutor(args.scheduler, quiet=not getattr(args, "verbose", 0))
    except (ImportError, ConnectionError, ValueError) as exc:
        raise CliError(str(exc)) from exc


def execute(
    args: argparse.Namespace,
    executor: SweepExecutor | None,
    store: ResultStore | None,
    command: str,
    run: Callable[[SweepExecutor], T],
) -> T | None:
    """``run(executor)``, on the Dask cluster when ``executor`` is ``None``; ``None`` when
    a worker was lost, said in one line. The executor and the store are closed after."""
    from ..sweep import WorkerLostError

    executor = executor or dask_executor(args)
    try:
        return run(executor)
    except WorkerLostError as exc:
        kept = f"; finished rows are in {args.out}: run again to resume" if store else ""
        print(f"puckboard {command}: error: {exc}{kept}", file=sys.stderr)
        return None
    finally:
        executor.close()
        if store is not None:
            store.close()


def run_options(
    args: argparse.Namespace, executor: SweepExecutor, store: ResultStore | None, label: str
) -> RunOptions:
    """The run's options as every experiment command takes them: on ``executor``,
    appending to ``store`` (``--out``), in ``--batch-size`` batches, ``--episode-timeout``
    each, progress labelled ``label`` unless ``-q``."""
    from ..sweep.options import RunOptions
    from ..sweep.progress import make_progress

    return RunOptions(
        executor=executor,
        store=store,
        batch_size=args.batch_size,
        progress=make_progress(enabled=not args.quiet, label=label),
        episode_timeout=args.episode_timeout,
    )


def wall_time(args: argparse.Namespace, result: ExperimentRun) -> float:
    """Seconds since the command began (workers' start-up and the plan included), which
    is what the user waited; the sweep's own ``wall_s`` where no start was noted."""
    started = getattr(args, "started", None)
    return result.wall_s if started is None else time.perf_counter() - started


def exit_status(
    args: argparse.Namespace, result: ExperimentRun, *, stored: bool, command: str = "sweep"
) -> int:
    """0; 130 after Ctrl-C, 143 after SIGTERM; 1 when every episode raised (a broken setup).
    Warnings name ``command`` (``sensitivity`` runs on this machinery too)."""
    errors = result.errors
    if errors:
        kinds = ", ".join(f"{n} {kind}" for kind, n in result.error_kinds().items())
        print(
            f"puckboard {command}: warning: {len(errors)} of {result.ran} episodes ended in "
            f"error ({kinds}; counted as failure 'error'; see the error and error_kind columns "
            f"of --out). First: {errors[0]}",
            file=sys.stderr,
        )
    if result.interrupted:
        stopped = "terminated" if result.terminated else "interrupted"
        if stored:
            said = (
                f"{result.ran} episodes of this run kept in {args.out}; run the same command "
                "again to resume"
            )
        else:  # no file: nothing survives this process, and a re-run starts from 0
            said = (
                f"{result.ran} episodes ran and none is kept: add --out FILE (.csv or "
                ".parquet) to keep finished episodes; the same command then resumes from it"
            )
        print(f"puckboard {command}: {stopped}; {said}", file=sys.stderr)
        return 143 if result.terminated else 130
    if result.ran and len(errors) == result.ran:
        return 1  # nothing ran properly: a broken setup, not a bad controller
    return 0
