"""Benchmark suite ``sweep``: episodes per second on 1 and 2 local processes and on Dask.

``puckboard bench --suite sweep [--steps N]`` runs the two-robot pass with the improved
controller and wheel-speed noise (so seeds differ) for ``N`` simulation steps per episode
(default 400, i.e. 20 simulated seconds; the judge may end an episode earlier), on:

* ``inline`` — one process, no pool: the cost of the episodes alone;
* ``local_1`` / ``local_2`` — :class:`LocalExecutor` with 1 and 2 worker processes;
* ``dask_2`` — :class:`DaskExecutor` on a 2-worker ``LocalCluster`` (one thread each).

Each executor is started and warmed up first (worker processes spawned, modules
imported), then the same plan runs ``REPEATS`` times; the figure is the median rate.
Start-up times are reported separately because a long sweep pays them once.

Goals: ``scaling_efficiency`` = rate(local_2) / (2 × rate(local_1)) ≥ 0.8 and
``dask_vs_local`` = rate(dask_2) / rate(local_2) ≥ 0.9. Both need a machine with two
otherwise idle cores; the load average is included so readers can judge.
"""

from __future__ import annotations

import dataclasses
import logging
import os
import statistics
import time
from typing import Any

from .executors import DaskExecutor, InlineExecutor, LocalExecutor, SweepExecutor
from .plan import SweepPlan
from .run import run_sweep

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


def _measure(
    executor: SweepExecutor, scene: Any, plan: SweepPlan, warmup: SweepPlan
) -> list[float]:
    run_sweep(warmup, scene, executor=executor, batch_size=1)
    rates = []
    for _ in range(REPEATS):
        result = run_sweep(plan, scene, executor=executor)
        if result.errors:
            raise RuntimeError(f"benchmark episodes failed: {result.errors[0]}")
        rates.append(result.ran / result.wall_s)
    return rates


def run_suite(steps: int | None = None) -> dict[str, Any]:
    """Episodes per second per executor; see the module docstring."""
    from ..sim.scenefile import load_scene

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

    rates: dict[str, list[float]] = {}
    startup: dict[str, float] = {}
    rates["inline"] = _measure(InlineExecutor(), scene, plan, warmup)
    for workers in (1, 2):
        with LocalExecutor(workers) as executor:
            t0 = time.perf_counter()
            run_sweep(warmup, scene, executor=executor, batch_size=1)
            startup[f"local_{workers}"] = time.perf_counter() - t0
            rates[f"local_{workers}"] = _measure(executor, scene, plan, warmup)
    dask_log = logging.getLogger("distributed")
    level = dask_log.level
    dask_log.setLevel(max(level, logging.WARNING))  # worker start/stop chatter
    try:
        t0 = time.perf_counter()
        with DaskExecutor(local_workers=2) as executor:
            run_sweep(warmup, scene, executor=executor, batch_size=1)
            startup["dask_2"] = time.perf_counter() - t0
            rates["dask_2"] = _measure(executor, scene, plan, warmup)
    except ImportError as exc:
        out["dask_2"] = f"skipped: {exc}"
    finally:
        dask_log.setLevel(level)

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
