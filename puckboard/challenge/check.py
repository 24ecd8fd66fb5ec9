"""``puckboard challenge check``: the grader's own checks on one file, before handing it in.

The file runs as grading runs it — in processes of its own, with the challenge's limits,
through the same pre-flight check (:func:`~puckboard.challenge.tasks.preflight`) — and
then on the practice cells' public seeds instead of the secret ones. The report ends in
one verdict: ``would be graded``, or the reason it would not be, or what to fix although
it would be (a layer that raises, an episode past the limit, ticks slower than the
control period). A file this check passes is never refused at grading.
"""

from __future__ import annotations

import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import ChallengeError
from ..sweep.executors import LocalExecutor, SweepExecutor
from ..sweep.host import Isolation
from ..sweep.options import RunOptions
from ..sweep.plan import SweepPlan
from ..sweep.progress import NullProgress, Progress
from ..sweep.run import SweepResult, drain, run_sweeps
from .grade import FILE_LIMIT
from .tasks import TIMED_TICKS, preflight

if TYPE_CHECKING:
    from .spec import Challenge

__all__ = ["CheckReport", "check_submission"]


@dataclass
class CheckReport:
    """What the check found, and its one verdict line."""

    challenge: Challenge
    file: Path
    preflight: dict[str, Any]
    practice: list[SweepResult] = field(default_factory=list)
    printed: list[str] = field(default_factory=list)
    wrote: list[str] = field(default_factory=list)
    interrupted: bool = False

    @property
    def refused(self) -> bool:
        return self.preflight.get("verdict") != "ok"

    def problems(self) -> list[str]:
        """What would keep it from being graded, or cost it at grading."""
        if self.refused:
            return [str(self.preflight.get("message"))]
        said = []
        ticks = self.preflight.get("ticks") or {}
        if ticks.get("error"):
            said.append(f"a layer raised in its first ticks: {ticks['error']}")
        period = ticks.get("period_s")
        if period and ticks.get("p95_s", 0.0) > period:
            layer = ticks.get("slowest_layer")
            slowest = (
                f" (slowest layer {layer}: {1e3 * ticks['slowest_layer_s']:.1f} ms a tick)"
                if layer
                else ""
            )
            said.append(
                f"its ticks take up to {1e3 * ticks['p95_s']:.0f} ms, over the "
                f"{1e3 * period:.0f} ms control period{slowest}: a real e-puck's loop could not "
                "keep up, and graded episodes may run past the wall-clock limit"
            )
        rows = [r for result in self.practice for r in result.rows if r.get("error")]
        if rows:
            total = sum(len(result.rows) for result in self.practice)
            said.append(
                f"{len(rows)} of {total} practice episodes ended in error: {rows[0]['error']}"
            )
        return said

    @property
    def verdict(self) -> str:
        problems = self.problems()
        if self.interrupted:
            return "check interrupted: run it again to finish"
        if self.refused:
            return f"would not be graded: {problems[0]}"
        if problems:
            return f"would be graded, but fix this first: {problems[0]}"
        return "would be graded"

    @property
    def ok(self) -> bool:
        return self.verdict == "would be graded"

    def to_dict(self) -> dict[str, Any]:
        return {
            "challenge": self.challenge.name,
            "file": str(self.file),
            "verdict": self.verdict,
            "ok": self.ok,
            "problems": self.problems(),
            "preflight": {k: v for k, v in self.preflight.items() if k != "spec"},
            "practice": [
                {
                    "cell": _cell(r),
                    "seed": int(r["seed"]),
                    "success": bool(r["success"]),
                    "failure": r["failure"],
                    "error": r["error"],
                    "progress_laps": r["progress_laps"],
                }
                for result in self.practice
                for r in sorted(result.rows, key=lambda r: int(r["seed"]))
            ],
            "printed_lines": len(self.printed),
            "wrote": list(self.wrote),
        }


def _cell(row: dict[str, Any]) -> str:
    import json

    return str(json.loads(str(row["params"])).get("label.cell"))


def check_submission(
    challenge: Challenge,
    file: str | Path,
    *,
    executor: SweepExecutor | None = None,
    progress: Progress | None = None,
) -> CheckReport:
    """Check ``file`` as grading would, then run it on the practice set (see the module
    docstring)."""
    path = Path(file)
    if not path.is_file():
        raise ChallengeError(f"no file {str(path)!r} to check")
    if path.suffix != ".py":
        raise ChallengeError(f"{str(path)!r} is not a .py file; a submission is one Python file")
    spec = f"{path.resolve().as_posix()}:{challenge.factory}"
    own = executor is None
    executor = executor or LocalExecutor(
        min(2, len(challenge.practice) * len(challenge.practice_seeds))
    )
    with tempfile.TemporaryDirectory(prefix="puckboard-check-") as folder:
        work = Path(folder) / "work"
        output = Path(folder) / "output.txt"
        memory = challenge.memory_mib
        isolation = Isolation(
            name="check",
            workdir=str(work),
            output=str(output),
            memory_bytes=None if memory is None else memory * 1024 * 1024,
            file_bytes=FILE_LIMIT,
        )
        cell = challenge.practice[0]
        task = (
            spec,
            challenge.factory,
            cell.scene,
            dict(cell.parameters),
            challenge.practice_seeds[0],
            TIMED_TICKS,
        )
        found: list[dict[str, Any]] = []
        try:
            stopped = drain(
                executor,
                lambda: executor.run(
                    preflight, [task], isolation=[isolation], unit_limit=challenge.check_timeout
                ),
                found.extend,
            )
            report = CheckReport(challenge, path, found[0] if found else {"verdict": "interrupted"})
            report.interrupted = stopped is not None
            if not report.refused and not report.interrupted:
                parts = [
                    (
                        SweepPlan(
                            c.scene.name,
                            controllers=(spec,),
                            seeds=challenge.practice_seeds,
                            fixed=dict(c.parameters),
                        ),
                        c.scene,
                    )
                    for c in challenge.practice
                ]
                options = RunOptions(
                    executor=executor,
                    progress=progress or NullProgress(),
                    episode_timeout=challenge.episode_timeout,
                    batch_size=1,
                )
                report.practice = run_sweeps(parts, options, isolation=lambda _: isolation)
                report.interrupted = any(r.interrupted for r in report.practice)
        finally:
            if own:
                executor.close()
        if output.exists():
            report.printed = output.read_text(encoding="utf-8", errors="replace").splitlines()
        if work.is_dir():
            report.wrote = sorted(
                p.relative_to(work).as_posix() for p in work.rglob("*") if p.is_file()
            )
    return report
