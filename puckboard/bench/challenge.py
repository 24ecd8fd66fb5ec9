"""Benchmark suite ``challenge``: what grading a class costs.

``puckboard bench --suite challenge [--steps N]`` grades a class of ``N`` submissions
(default 30) on the shipped challenge (``pass``: four graded cells of eight episodes,
and the three shipped controllers as baselines) on two local worker processes, as
``puckboard challenge grade`` does, into a fresh output folder. The class is the shipped
controllers' factories and the tutorial's controller (its ``my_controller.py``, which
defines ``make_controller``), in turn, each file made distinct by a comment
so that each is a version of its own.

Reported: the wall time and each step's (the pre-flight checks, the graded episodes,
the replays), the episodes run and per second, the load average before and after (the
machine may be shared) and, where the platform tells it, the workers' CPU seconds: on a
machine busy with other work the wall time grows, the CPU seconds hardly do, and half of
them is what two idle cores would take.
"""

from __future__ import annotations

import tempfile
from collections import Counter
from pathlib import Path
from typing import Any

from ..sweep.signals import stop_on_terminate
from .transfer import load_average, on_local_workers, student_controller

__all__ = ["CHALLENGE", "SUBMISSIONS", "WORKERS", "make_class", "run_suite"]

CHALLENGE = "pass"
#: Submissions in the class when ``--steps`` gives no number.
SUBMISSIONS = 30
WORKERS = 2
#: The secret the benchmark's seeds come from (a benchmark has nothing to hide).
_SECRET = "benchmark class secret"


def make_class(n: int, folder: Path) -> list[str]:
    """``n`` submission files in ``folder``, the shipped controllers' factories and the
    tutorial's controller in turn; returns what each one is."""
    folder.mkdir(parents=True, exist_ok=True)
    kinds = ["robust", "improved", "stock", "tutorial"]
    tutorial = student_controller(folder.parent)
    made = []
    for i in range(n):
        kind = kinds[i % len(kinds)]
        if kind == "tutorial":
            text = Path(tutorial.rpartition(":")[0]).read_text(encoding="utf-8")
        else:
            text = (
                f"from puckboard.behaviours import {kind}\n\n\n"
                f"def make_controller(**params):\n    return {kind}(**params)\n"
            )
        (folder / f"student_{i:02d}.py").write_text(f"# student {i}\n{text}", encoding="utf-8")
        made.append(kind)
    return made


def run_suite(steps: int | None = None) -> dict[str, Any]:
    """A class's grading on two local workers; see the module docstring. ``steps``: how
    many submissions (default 30)."""
    with stop_on_terminate(), tempfile.TemporaryDirectory() as folder:
        return _run_suite(steps or SUBMISSIONS, Path(folder))


def _run_suite(n: int, folder: Path) -> dict[str, Any]:
    from ..challenge import load_challenge
    from ..challenge.grade import grade
    from ..challenge.seeds import Secret

    challenge = load_challenge(CHALLENGE)
    kinds = make_class(n, folder / "class")
    out: dict[str, Any] = {
        "challenge": challenge.name,
        "submissions": n,
        "class": {k: kinds.count(k) for k in dict.fromkeys(kinds)},
        "baselines": list(challenge.baselines),
        "graded_episodes_per_entry": len(challenge.graded) * challenge.episodes,
        "workers": WORKERS,
        "load_average_before": load_average(),
    }
    secret = Secret(_SECRET, challenge.name)
    grading, measured = on_local_workers(
        lambda executor: grade(
            challenge, folder / "class", secret, folder / "out", executor=executor
        ),
        WORKERS,
    )
    wall = measured["wall_s"]
    out.update(
        wall_s=wall,
        phase_s={k: round(v, 1) for k, v in grading.phase_s.items()},
        episodes=grading.ran,
        episodes_per_s=round(grading.ran / wall, 2) if wall else None,
        verdicts=dict(Counter(s.verdict for s in grading.standings)),
        workers_cpu_s=measured["workers_cpu_s"],
        idle_two_cores_estimate_s=measured["idle_two_cores_estimate_s"],
        load_average_after=load_average(),
    )
    return out
