"""Benchmark suite ``transfer``: what the flagship transfer report costs.

The flagship report (docs/transfer.md) judges three controllers, ``robust``, ``improved``
and a student's (the tutorial's ``my_controller.py:my_controller``), with both profiles
(``epuck``, ``epuck-vrep``) on both pass scenes (``two-robot-pass`` and
``two-robot-pass-bend``) on every held-out family, at the command's default seeds.
``puckboard bench --suite transfer [--steps N]`` runs exactly that on two local worker
processes (``N``: seeds per model, default the command's) and times it from the start of
the workers to the last row. The student's controller is the tutorial's
``# my_controller.py`` block (:mod:`.tutorial_controller`), saved as a student saves it.

Reported: the wall time, episodes per second, the load average before and after (the
machine may be shared) and, where the platform tells it, the workers' CPU seconds: on a
machine busy with other work the wall time grows, the CPU seconds hardly do, and half of
them is what two idle cores would take.
"""

from __future__ import annotations

import os
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

from ..sweep.defaults import TRANSFER_SEEDS
from ..sweep.executors import LocalExecutor
from ..sweep.plan import parse_seeds
from ..sweep.signals import stop_on_terminate

__all__ = [
    "FLAGSHIP_CONTROLLERS",
    "FLAGSHIP_PROFILES",
    "FLAGSHIP_SCENES",
    "children_cpu_s",
    "flagship_plan",
    "load_average",
    "on_local_workers",
    "run_suite",
    "student_controller",
]

FLAGSHIP_SCENES = ("two-robot-pass", "two-robot-pass-bend")
FLAGSHIP_PROFILES = ("epuck", "epuck-vrep")
FLAGSHIP_CONTROLLERS = ("robust", "improved")
_SEEDS = parse_seeds(TRANSFER_SEEDS)
#: The flagship's seeds: a transfer report's default (puckboard.sweep.defaults).
FLAGSHIP_SEEDS = (_SEEDS.start, _SEEDS.stop)
WORKERS = 2
T = TypeVar("T")
#: What the flagship report should take on two cores (the issue's target).
TARGET_S = 300.0


def load_average() -> float | None:
    """The machine's load average over the last minute (None where not told)."""
    return round(os.getloadavg()[0], 2) if hasattr(os, "getloadavg") else None


def children_cpu_s() -> float | None:
    """CPU seconds of this process's ended children (the workers, once closed)."""
    try:
        import resource
    except ImportError:  # Windows
        return None
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def student_controller(folder: Path) -> str:
    """The tutorial's ``my_controller.py`` saved in ``folder``, as its spec
    (``…/my_controller.py:my_controller``): run as a student's file is."""
    from .tutorial_controller import FILE_NAME, SOURCE

    path = folder / FILE_NAME
    path.write_text(SOURCE, encoding="utf-8")
    return f"{path}:{path.stem}"


def run_suite(steps: int | None = None) -> dict[str, Any]:
    """The flagship report's wall time on two local workers; see the module docstring.
    ``steps``: seeds per model (default: the flagship's)."""
    with stop_on_terminate(), tempfile.TemporaryDirectory() as folder:
        return _run_suite(steps or FLAGSHIP_SEEDS[1] - FLAGSHIP_SEEDS[0], Path(folder))


def flagship_plan(n: int, folder: Path) -> tuple[Any, dict[str, Any]]:
    """The flagship report at ``n`` seeds per model: its plan and every scene it runs on
    (by name); the student's controller is saved in ``folder``."""
    from ..scenario.scenefile import load_scene
    from ..transfer import FAMILIES, transfer_plan

    controllers = [*FLAGSHIP_CONTROLLERS, student_controller(folder)]
    scenes = [load_scene(name) for name in FLAGSHIP_SCENES]
    replacements = {f.scene: load_scene(f.scene) for f in FAMILIES if f.scene is not None}
    plan = transfer_plan(
        scenes,
        controllers=controllers,
        profiles={s.name: list(FLAGSHIP_PROFILES) for s in scenes},
        seeds=range(FLAGSHIP_SEEDS[0], FLAGSHIP_SEEDS[0] + n),
        families=FAMILIES,
        replacements=replacements,
    )
    return plan, {**replacements, **{s.name: s for s in scenes}}


def _run_suite(n: int, folder: Path) -> dict[str, Any]:
    from ..sweep.options import RunOptions
    from ..transfer import run_transfer_plan

    plan, scenes = flagship_plan(n, folder)
    out: dict[str, Any] = {
        "scenes": list(FLAGSHIP_SCENES),
        "profiles": list(FLAGSHIP_PROFILES),
        "controllers": [*FLAGSHIP_CONTROLLERS, "my_controller"],
        "student_controller": "tutorial's my_controller.py",
        "families": [f.name for f in plan.families],
        "seeds_per_model": n,
        "episodes": len(plan),
        "workers": WORKERS,
        "load_average_before": load_average(),
    }
    result, measured = on_local_workers(
        lambda executor: run_transfer_plan(plan, scenes, RunOptions(executor=executor))
    )
    wall = measured["wall_s"]
    out.update(
        wall_s=wall,
        episodes_per_s=round(result.ran / wall, 2) if wall else None,
        errors=len(result.errors),
        workers_cpu_s=measured["workers_cpu_s"],
        idle_two_cores_estimate_s=measured["idle_two_cores_estimate_s"],
        target_s=TARGET_S,
        load_average_after=load_average(),
    )
    return out


def on_local_workers(
    work: Callable[[LocalExecutor], T], workers: int = WORKERS
) -> tuple[T, dict[str, Any]]:
    """``work(executor)`` on ``workers`` local workers started for it, and what it took:
    ``wall_s`` from the workers' start to the end, and where the platform tells it the
    workers' CPU seconds (``workers_cpu_s``) and half of them
    (``idle_two_cores_estimate_s``, what two idle cores would take)."""
    cpu_before = children_cpu_s()
    t0 = time.perf_counter()
    executor = LocalExecutor(workers)
    try:
        executor.start()
        result = work(executor)
    finally:
        executor.close()
    wall = time.perf_counter() - t0
    cpu_after = children_cpu_s()
    cpu = None if cpu_before is None or cpu_after is None else cpu_after - cpu_before
    return result, {
        "wall_s": round(wall, 1),
        "workers_cpu_s": None if cpu is None else round(cpu, 1),
        "idle_two_cores_estimate_s": None if cpu is None else round(cpu / 2, 1),
    }
