"""``puckboard challenge``: a class challenge, from the student's check to the leaderboard.

  list    the shipped challenges, one a line, name first
  show    print a challenge file (to read its practice set, or to start your own)
  check   run the grader's own checks on FILE.py and its practice episodes, before
          handing it in: one verdict line, 'would be graded' or why not
  grade   grade a folder of submissions, each in processes of its own, on the graded
          cells and the seeds drawn from --secret; resumable; writes DIR/leaderboard.html
          and DIR/results.csv

The graded seeds are never printed, nor written anywhere, until 'grade ... --reveal'
after the deadline. docs/challenges.md documents the challenge file; docs/lecturer-notes.md
("Running a competition") the whole course of a challenge.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from .checks import check_writable
from .errors import CliError
from .experiment_options import add_quiet, dask_executor, with_executor
from .parsing import help_text

if TYPE_CHECKING:
    from ..challenge.check import CheckReport
    from ..challenge.grade import Grading
    from ..challenge.spec import Challenge
    from ..sweep.executors import SweepExecutor

#: The challenge ``check`` runs when none is named.
DEFAULT_CHALLENGE = "pass"


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    parser = subparsers.add_parser(
        "challenge",
        help="a class challenge: check a submission, grade a class, make the leaderboard",
        description=help_text(__doc__),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    actions = parser.add_subparsers(dest="action", metavar="ACTION")
    listing = actions.add_parser("list", help="the shipped challenges, one a line")
    listing.set_defaults(func=_list)
    show = actions.add_parser("show", help="print a challenge file")
    show.add_argument("challenge", metavar="NAME|FILE", help="a shipped challenge or a file")
    show.set_defaults(func=_show)
    _register_check(actions)
    _register_grade(actions)
    parser.set_defaults(func=_no_action)


def _register_check(actions: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    check = actions.add_parser(
        "check",
        help="check FILE.py as grading would, on the practice set",
        description=(
            "Import FILE.py in a process of its own, build its controller, time its ticks "
            "against the control period and run a few practice episodes per cell, as grading "
            "does; end with one verdict line. Exit status 0 when it would be graded as it is."
        ),
    )
    check.add_argument("file", type=Path, metavar="FILE.py", help="the file you will hand in")
    check.add_argument(
        "--challenge",
        default=DEFAULT_CHALLENGE,
        metavar="NAME|FILE",
        help=f"the challenge, shipped or a file your lecturer gave (default: {DEFAULT_CHALLENGE})",
    )
    check.add_argument("--json", action="store_true", help="print the report as one JSON object")
    add_quiet(check)
    check.set_defaults(func=_check)


def _register_grade(actions: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    grade = actions.add_parser(
        "grade",
        help="grade a folder of submissions and write the leaderboard",
        description=(
            "Grade every submission in SUBMISSIONS_DIR (NAME.py, or a folder NAME/ holding one "
            ".py file) on the challenge's graded cells, each in processes of its own, on seeds "
            "drawn from the secret, and write DIR/leaderboard.html, DIR/results.csv and a "
            "table. The same command resumes after Ctrl-C or a kill, and grades only new or "
            "changed files."
        ),
    )
    grade.add_argument(
        "challenge", metavar="CHALLENGE", help="a shipped challenge or a challenge file"
    )
    grade.add_argument("submissions", type=Path, metavar="SUBMISSIONS_DIR")
    secret = grade.add_mutually_exclusive_group()
    secret.add_argument(
        "--secret", metavar="WORD", help="the secret the graded seeds come from (visible in ps)"
    )
    secret.add_argument(
        "--secret-file", type=Path, metavar="FILE", help="read the secret from FILE (preferred)"
    )
    grade.add_argument(
        "--out", type=Path, required=True, metavar="DIR", help="the grading's folder (resumable)"
    )
    where = grade.add_mutually_exclusive_group()
    where.add_argument(
        "--workers", type=int, metavar="N", help="local worker processes (default: all CPUs)"
    )
    where.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="run on an existing Dask cluster, e.g. tcp://10.0.0.5:8786 (needs puckboard[dask]; "
        "its workers must be able to start processes: see docs/challenges.md)",
    )
    grade.add_argument(
        "--final",
        action="store_true",
        help="freeze the final ranking on the versions this run grades (at the deadline)",
    )
    grade.add_argument(
        "--reveal",
        action="store_true",
        help="after the deadline: show the graded seeds in every output (freezes the final "
        "ranking first if --final never did)",
    )
    grade.add_argument("--json", action="store_true", help="print the leaderboard's rows as JSON")
    add_quiet(grade)
    grade.set_defaults(func=_grade)


def _no_action(args: argparse.Namespace) -> int:
    raise CliError("which action? puckboard challenge list | show NAME | check FILE.py | grade ...")


def _challenge(ref: str) -> Challenge:
    from ..challenge import load_challenge
    from ..errors import ChallengeError

    try:
        return load_challenge(ref)
    except ChallengeError as exc:
        raise CliError(str(exc)) from None


def _list(args: argparse.Namespace) -> int:
    from ..challenge import challenge_names

    for name in challenge_names():
        challenge = _challenge(name)
        cells = f"{len(challenge.graded)} graded cells × {challenge.episodes} episodes"
        print(f"{name}  {challenge.title} ({cells})")
    return 0


def _show(args: argparse.Namespace) -> int:
    from importlib import resources

    from ..challenge import challenge_names

    challenge = _challenge(args.challenge)  # checked, so a broken file is said in one line
    if args.challenge in challenge_names():
        entry = (
            resources.files("puckboard.challenge")
            .joinpath("shipped")
            .joinpath(f"{args.challenge}.toml")
        )
        text = entry.read_text(encoding="utf-8")
    else:
        text = Path(challenge.source).read_text(encoding="utf-8")
    print(text, end="" if text.endswith("\n") else "\n")
    return 0


# -- check ---------------------------------------------------------------------------------
def _check(args: argparse.Namespace) -> int:
    from ..challenge.check import check_submission
    from ..errors import ChallengeError
    from ..sweep import make_progress

    challenge = _challenge(args.challenge)
    try:
        report = check_submission(
            challenge, args.file, progress=make_progress(enabled=not args.quiet)
        )
    except ChallengeError as exc:
        raise CliError(str(exc)) from None
    if args.json:
        print(json.dumps(report.to_dict(), indent=2))
    else:
        _print_check(report)
    if report.interrupted:
        raise KeyboardInterrupt
    return 0 if report.ok else 1


def _print_check(report: CheckReport) -> None:
    from ..sweep.summary import format_table

    pre = report.preflight
    print(f"{report.file.name} on challenge {report.challenge.name!r} ({report.challenge.title})")
    print()
    if report.refused:
        if pre.get("details"):
            print(str(pre["details"]).rstrip())
            print()
        print(f"pre-flight: {pre.get('message')}")
    else:
        layers = pre.get("layers") or []
        print(f"pre-flight: imports; {report.challenge.factory}() builds a controller of "
              f"{len(layers)} layers: {', '.join(layers)}")  # fmt: skip
        ticks = pre.get("ticks") or {}
        if ticks.get("ticks"):
            slow = ""
            if ticks.get("slowest_layer"):
                layer, spent = ticks["slowest_layer"], 1e3 * ticks["slowest_layer_s"]
                slow = f"; slowest layer {layer}, {spent:.2f} ms"
            print(
                f"ticks: median {1e3 * ticks['median_s']:.2f} ms, 95th percentile "
                f"{1e3 * ticks['p95_s']:.2f} ms over {ticks['ticks']} ticks (control period "
                f"{1e3 * ticks['period_s']:.0f} ms){slow}"
            )
        if ticks.get("error"):
            print(str(ticks.get("details") or ticks["error"]).rstrip())
    if report.practice:
        rows = []
        for result in report.practice:
            for row in sorted(result.rows, key=lambda r: int(r["seed"])):
                cell = json.loads(str(row["params"])).get("label.cell")
                outcome = "success" if row["success"] else (row["failure"] or "failed")
                if row.get("error"):
                    outcome = f"error ({row.get('error_kind')}): {row['error']}"[:70]
                rows.append(
                    [str(cell), str(row["seed"]), f"{float(row['progress_laps']):.2f}", outcome]
                )
        print()
        print("practice episodes (public seeds):")
        print(format_table(["cell", "seed", "progress", "outcome"], rows, right={1, 2}))
    if report.printed:
        print()
        print(
            f"it printed {len(report.printed)} lines (at grading they go to a file, not the "
            "class's table); first:"
        )
        for line in report.printed[:3]:
            print(f"  {line}")
    if report.wrote:
        print(
            f"it wrote files: {', '.join(report.wrote[:5])} (at grading, into a folder of its own)"
        )
    print()
    print(report.verdict)


# -- grade ---------------------------------------------------------------------------------
def _grade(args: argparse.Namespace) -> int:
    from ..sweep.signals import stop_on_terminate

    if args.workers is not None and args.workers < 1:
        raise CliError(f"--workers must be at least 1, got {args.workers}")
    if args.out.exists() and not args.out.is_dir():
        raise CliError(f"--out {str(args.out)!r} is a file; name a folder for the grading")
    check_writable(args.out, "--out", folder=True)
    with stop_on_terminate():  # SIGTERM stops as Ctrl-C does: every finished row kept
        return with_executor(args, _run_grade)


def _run_grade(args: argparse.Namespace, executor: SweepExecutor | None) -> int:
    from ..challenge.grade import grade
    from ..challenge.seeds import read_secret
    from ..errors import ChallengeError
    from ..sweep import make_progress
    from ..sweep.signals import interrupts_deferred

    with interrupts_deferred():  # see cli/sweep.py: a Ctrl-C while importing waits
        challenge = _challenge(args.challenge)
        try:
            secret = read_secret(args.secret, args.secret_file, challenge.name)
        except ChallengeError as exc:
            raise CliError(str(exc)) from None
    on = executor or dask_executor(args)
    try:
        grading = grade(
            challenge,
            args.submissions,
            secret,
            args.out,
            executor=on,
            progress=make_progress(enabled=not args.quiet, label="grade"),
            reveal=args.reveal,
            final=args.final,
        )
    except ChallengeError as exc:
        raise CliError(str(exc)) from None
    except RuntimeError as exc:
        from ..sweep.cluster import ClusterSetupError

        if isinstance(exc, ClusterSetupError):
            raise CliError(str(exc)) from None
        raise
    finally:
        on.close()
    _report(args, grading)
    if grading.interrupted:
        stopped = "terminated" if grading.terminated else "interrupted"
        print(
            f"puckboard challenge: {stopped}; {grading.ran} episodes of this run kept in "
            f"{args.out}; run the same command again to resume",
            file=sys.stderr,
        )
        return 143 if grading.terminated else 130
    return 0


def _report(args: argparse.Namespace, grading: Grading) -> None:
    from ..challenge.leaderboard import format_leaderboard

    if args.json:
        print(json.dumps(grading.to_dict(), indent=2))
        return
    challenge = grading.challenge
    new = f"{len(grading.new)} new or changed, " if grading.new else ""
    print(
        f"{challenge.name}: {new}{grading.checked} checked, {grading.ran} episodes run, "
        f"{grading.skipped} already graded; {grading.wall_s:.1f} s"
    )
    print()
    title = "final ranking" if grading.view == "final" else "ranking (latest versions)"
    print(f"{title}:")
    print(format_leaderboard(grading))
    said = [s for s in grading.standings if s.verdict_text or s.remarks]
    if said:
        print()
        for s in said:
            words = "; ".join([s.verdict_text] * bool(s.verdict_text) + s.remarks)
            print(f"{s.name}: {s.verdict}: {words}")
    if grading.latest is not None:
        print()
        print("latest versions (after the final ranking, which they do not change):")
        print(format_leaderboard(grading, grading.latest))
    if grading.seeds is not None:
        print()
        print("graded seeds (revealed):")
        for cell, seeds in grading.seeds.items():
            print(f"  {cell}: {', '.join(map(str, seeds))}")
    print()
    print(f"leaderboard: {(args.out / 'leaderboard.html').resolve().as_uri()}")
