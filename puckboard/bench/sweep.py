"""Benchmark suite ``sweep``: episodes per second on 1 and 2 local processes and on Dask.

``puckboard bench --suite sweep [--steps N]`` runs the two-robot pass with the improved
controller and wheel-speed noise (so seeds differ) for ``N`` simulation steps per episode
(default 400, i.e. 20 simulated seconds; the judge may end an episode earlier), on:

* ``inline`` — one process, no pool: the cost of the episodes alone;
* ``local_1`` / ``local_2`` — :class:`LocalExecutor` with 1 and 2 worker processes;
* ``dask_2`` — :class:`DaskExecutor` on a 2-worker ``LocalCluster`` (one thread each).

Every executor is started and warmed up first (worker processes spawned, modules
imported); then the same plan runs ``REPEATS`` times on each, the executors taking turns
so that a change in load on a shared machine affects them alike; the figure is the
median rate.
Start-up times are reported separately because a long sweep pays them once.

Goals: ``scaling_efficiency`` = rate(local_2) / (2 × rate(local_1)) ≥ 0.8 and
``dask_vs_local`` = rate(dask_2) / rate(local_2) ≥ 0.9. Both need a machine with two
otherwise idle cores; the load average is included so readers can judge.
"""

from __future__ import annotations

import dataclasses
import json
import logging
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..sweep.cluster import DaskExecutor
from ..sweep.executors import InlineExecutor, LocalExecutor, SweepExecutor
from ..sweep.options import RunOptions
from ..sweep.plan import EpisodeSpec, SweepPlan
from ..sweep.run import SweepResult, run_sweep
from ..sweep.signals import Terminated, stop_on_terminate
from ..sweep.worker import worker_ready
from .sweep_model import episodes_from_rows, model_sweep, read_rows

if TYPE_CHECKING:
    from ..scenario.scene import Scene

__all__ = ["run_suite"]

REPEATS = 3
EPISODES = 24
DEFAULT_STEPS = 400
#: Worker counts the scheduling model is evaluated for.
MODEL_WORKERS = (1, 2, 4, 8, 16)


def _plan(scenario: str, duration: float, episodes: int) -> SweepPlan:
    return SweepPlan.from_specs(
        scenario,
        controllers=["improved"],
        seeds=range(episodes),
        fixed={"duration": duration, "noise.wheel_speed": 0.05},
    )


def _sweep(executor: SweepExecutor, scene: Scene, plan: SweepPlan, **options: Any) -> SweepResult:
    """:func:`run_sweep`, except that Ctrl-C (or SIGTERM) ends the benchmark after the
    sweep has stopped its workers, rather than leaving it to time a partial sweep."""
    result = run_sweep(plan, scene, RunOptions(executor=executor, **options))
    if result.interrupted:
        raise Terminated if result.terminated else KeyboardInterrupt
    return result


def _rate(executor: SweepExecutor, scene: Scene, plan: SweepPlan) -> tuple[float, SweepResult]:
    result = _sweep(executor, scene, plan)
    if result.errors:
        raise RuntimeError(f"benchmark episodes failed: {result.errors[0]}")
    return result.ran / result.wall_s, result


def run_suite(steps: int | None = None, durations: Path | None = None) -> dict[str, Any]:
    """Episodes per second per executor, the overheads of a sweep and the scheduling
    model fed with them; see the module docstring."""
    with stop_on_terminate():
        return _run_suite(steps, durations)


def _run_suite(steps: int | None, durations: Path | None) -> dict[str, Any]:
    from ..scenario.scenefile import load_scene

    model_rows = read_rows(durations) if durations is not None else None  # refuse a bad file first
    scene = load_scene("two-robot-pass")
    n_steps = steps or DEFAULT_STEPS
    duration = n_steps * scene.dt
    scene = dataclasses.replace(scene, duration=duration)
    plan = _plan(scene.name, duration, EPISODES)
    warmup = _plan(scene.name, 10 * scene.dt, 4)
    out: dict[str, Any] = {
        "scene": scene.name,
        "controller": "improved",
        "steps_per_episode_max": n_steps,
        "episodes_per_repeat": EPISODES,
        "repeats": REPEATS,
    }
    if hasattr(os, "getloadavg"):
        out["load_average_before"] = round(os.getloadavg()[0], 2)

    executors: dict[str, SweepExecutor] = {"inline": InlineExecutor()}
    startup: dict[str, float] = {}
    spawn: dict[str, float] = {}
    ready: dict[str, list[float]] = {}
    try:
        for name, make in (
            ("local_1", lambda: LocalExecutor(1)),
            ("local_2", lambda: LocalExecutor(2)),
            ("dask_2", lambda: DaskExecutor(local_workers=2)),
        ):
            t0 = time.perf_counter()
            m0 = time.monotonic()
            try:
                started = executors[name] = make()
            except ImportError as exc:
                out[name] = f"skipped: {exc}"
                continue
            if isinstance(started, LocalExecutor):
                started.start()
                spawn[name] = time.perf_counter() - t0
                ready[name] = _ready_times(started, m0)
            # spawn the workers and import everything before timing anything
            _sweep(started, scene, warmup, batch_size=1)
            startup[name] = time.perf_counter() - t0
        # Interleave the executors repeat by repeat, so a change in the machine's load
        # hits all of them alike instead of spoiling one.
        rates: dict[str, list[float]] = {name: [] for name in executors}
        inline: list[SweepResult] = []
        for _ in range(REPEATS):
            for name, executor in executors.items():
                rate, result = _rate(executor, scene, plan)
                rates[name].append(rate)
                if name == "inline":
                    inline.append(result)
        round_trip = _task_round_trip(executors["local_2"], scene)
    finally:
        for executor in executors.values():
            executor.close()

    median = {name: statistics.median(values) for name, values in rates.items()}
    out["episodes_per_s"] = median
    out["episodes_per_s_min_max"] = {n: [min(v), max(v)] for n, v in rates.items()}
    out["startup_s"] = startup
    out["scaling_efficiency"] = median["local_2"] / (2 * median["local_1"])
    if "dask_2" in median:
        out["dask_vs_local"] = median["dask_2"] / median["local_2"]

    # where a sweep's time goes besides its episodes (the inputs of the model below)
    outside = [(r.wall_s - sum(row["wall_s"] for row in r.rows)) / r.ran for r in inline]
    overheads = {
        "spawn_s_per_worker": spawn["local_2"] / 2,
        "worker_ready_s": ready,
        "task_round_trip_ms": round_trip * 1e3,
        "collect_ms_per_row": _collect_seconds(inline[0].rows) * 1e3,
        "episode_outside_its_timer_ms": statistics.median(outside) * 1e3,
    }
    # what today's command line waits for its workers, having started them first
    overheads["command_line_startup_s"] = {w: _command_line_startup(w) for w in (1, 2)}
    out["overheads"] = overheads
    if model_rows is not None:
        episodes = episodes_from_rows(model_rows)
        model_scene = _scene_or_none(str(model_rows[0].get("scenario", "")))
    else:
        episodes = [(spec, row["wall_s"]) for spec, row in _in_plan_order(plan, inline[0])]
        model_scene = scene
    # Start-up on W workers: as measured for 1 and 2, and for more the slower of two
    # plus creating the others one after the other (each then starts up in parallel,
    # given a core of its own). Before: the sweep waited for all of it; today the
    # command line overlaps it with its own preparation.
    # Two workers start no sooner than one: where noise measured them faster, the model
    # takes one worker's figure (it would otherwise model an efficiency above 1).
    per_worker = overheads["spawn_s_per_worker"]
    ready_1 = max(ready["local_1"])
    ready_2 = max(ready_1, max(ready["local_2"]))
    command_line = overheads["command_line_startup_s"]
    waits_2 = max(command_line[1], command_line[2])
    out["model"] = model_sweep(
        episodes,
        scene=model_scene,
        startup_s={w: ready_2 + max(0, w - 2) * per_worker
                   for w in MODEL_WORKERS} | {1: ready_1},
        startup_after_s={w: waits_2 + max(0, w - 2) * per_worker
                         for w in MODEL_WORKERS} | {1: command_line[1]},
        per_episode_s=overheads["episode_outside_its_timer_ms"] / 1e3,
        per_task_s=round_trip,
        workers=MODEL_WORKERS,
    )  # fmt: skip
    out["model"]["durations_from"] = str(durations) if durations else "the inline runs above"
    if hasattr(os, "getloadavg"):
        out["load_average_after"] = round(os.getloadavg()[0], 2)
    return out


def _command_line_startup(workers: int, repeats: int = 3) -> float:
    """Seconds ``puckboard sweep`` (a fresh process) reports for one one-step episode
    per worker: what it still waits for its workers after preparing the sweep; median."""
    scene = "two-robot-pass"
    command = [
        sys.executable, "-m", "puckboard", "sweep", scene, "--controller", "improved",
        "--seeds", f"0:{workers}", "--duration", "0.05", "--workers", str(workers),
        "--quiet", "--json",
    ]  # fmt: skip
    figures = []
    for _ in range(repeats):
        done = subprocess.run(command, capture_output=True, text=True, check=True)
        figures.append(float(json.loads(done.stdout)["wall_s"]))
    return statistics.median(figures)


def _ready_times(executor: LocalExecutor, since: float) -> list[float]:
    """Seconds from ``since`` until each worker had started up (spawned, imported)."""
    seen: dict[int, float] = {}
    deadline = time.monotonic() + 60.0
    while len(seen) < executor.workers and time.monotonic() < deadline:
        for pid, at in executor.run(worker_ready, [()] * executor.workers):
            if at is not None:
                seen[pid] = at - since
        time.sleep(0.02)  # an idle worker takes every probe; give the others their turn
    return sorted(seen.values())


def _task_round_trip(executor: SweepExecutor, scene: Scene, tasks: int = 200) -> float:
    """Seconds per task of empty batches: sending the scene, returning no rows."""
    from ..sweep.worker import run_batch

    empty: tuple[Any, ...] = (scene, scene.name, [], None, logging.ERROR, None, None)
    t0 = time.perf_counter()
    for _ in executor.run(run_batch, [empty] * tasks):
        pass
    return (time.perf_counter() - t0) / tasks


def _collect_seconds(rows: list[dict[str, Any]]) -> float:
    """What the sweep's own process spends per row: the CSV file and the summary."""
    from ..sweep.rows import Outcome
    from ..sweep.store import open_store

    with tempfile.TemporaryDirectory() as folder:
        store = open_store(Path(folder) / "rows.csv")
        t0 = time.perf_counter()
        for row in rows:
            store.append([row])
            Outcome.from_row(row)
        elapsed = time.perf_counter() - t0
        store.close()
    return elapsed / len(rows)


def _in_plan_order(plan: SweepPlan, result: SweepResult) -> list[tuple[EpisodeSpec, Any]]:
    by_key = {row["key"]: row for row in result.rows}
    return [(spec, by_key[spec.key(plan.scenario)]) for spec in plan.episodes()]


def _scene_or_none(name: str) -> Any:
    """The shipped scene of that name, for the model's step limits (None: all equal)."""
    from ..scenario.scenefile import load_scene

    try:
        return load_scene(name)
    except (ValueError, OSError):
        return None
