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
import os
import statistics
import time
from typing import Any

from ..sweep.cluster import DaskExecutor
from ..sweep.executors import InlineExecutor, LocalExecutor, SweepExecutor
from ..sweep.plan import SweepPlan
from ..sweep.run import SweepResult, run_sweep
from ..sweep.signals import Terminated, stop_on_terminate

__all__ = ["run_suite"]

REPEATS = 3
EPISODES = 24
DEFAULT_STEPS = 400


def _plan(scenario: str, duration: float, episodes: int) -> SweepPlan:
    return SweepPlan.from_specs(
        scenario,
        controllers=["improved"],
        seeds=range(episodes),
        fixed={"duration": duration, "noise.wheel_speed": 0.05},
    )


def _sweep(executor: SweepExecutor, scene: Any, plan: SweepPlan, **options: Any) -> SweepResult:
    """:func:`run_sweep`, except that Ctrl-C (or SIGTERM) ends the benchmark after the
    sweep has stopped its workers, rather than leaving it to time a partial sweep."""
    result = run_sweep(plan, scene, executor=executor, **options)
    if result.interrupted:
        raise Terminated if result.terminated else KeyboardInterrupt
    return result


def _rate(executor: SweepExecutor, scene: Any, plan: SweepPlan) -> float:
    result = _sweep(executor, scene, plan)
    if result.errors:
        raise RuntimeError(f"benchmark episodes failed: {result.errors[0]}")
    return result.ran / result.wall_s


def run_suite(steps: int | None = None) -> dict[str, Any]:
    """Episodes per second per executor; see the module docstring."""
    with stop_on_terminate():
        return _run_suite(steps)


def _run_suite(steps: int | None) -> dict[str, Any]:
    from ..scenario.scenefile import load_scene

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
    try:
        for name, make in (
            ("local_1", lambda: LocalExecutor(1)),
            ("local_2", lambda: LocalExecutor(2)),
            ("dask_2", lambda: DaskExecutor(local_workers=2)),
        ):
            t0 = time.perf_counter()
            try:
                executors[name] = make()
            except ImportError as exc:
                out[name] = f"skipped: {exc}"
                continue
            # spawn the workers and import everything before timing anything
            _sweep(executors[name], scene, warmup, batch_size=1)
            startup[name] = time.perf_counter() - t0
        # Interleave the executors repeat by repeat, so a change in the machine's load
        # hits all of them alike instead of spoiling one.
        rates: dict[str, list[float]] = {name: [] for name in executors}
        for _ in range(REPEATS):
            for name, executor in executors.items():
                rates[name].append(_rate(executor, scene, plan))
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
    if hasattr(os, "getloadavg"):
        out["load_average_after"] = round(os.getloadavg()[0], 2)
    return out
