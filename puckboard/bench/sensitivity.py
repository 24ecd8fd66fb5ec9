"""Benchmark suite ``sensitivity``: what the joint method's flagship analysis costs.

The flagship analysis (docs/sweeps.md) is the two-robot pass, two controllers × the
``epuck`` and ``epuck-vrep`` profiles, :data:`FLAGSHIP_N` plausible robots each: 1,200
full-length episodes and four analyses. ``puckboard bench --suite sensitivity
[--steps N]`` runs a small version of it on two local worker processes: the improved
controller on both profiles, ``N`` plausible robots each (default 20, full-length
episodes), then times the estimators on what ran. The tutorial's controller is a
reader's file, not part of the package, so it is not run here; ``improved`` ends a few
more of its episodes early (``lost_line``), so the figure is a lower bound.

Reported: episodes per second, the analysis's seconds per controller × profile, and
``flagship_estimate_s``, the whole flagship at those rates (the analysis's own cost is
mostly per number, so it is counted as measured here). The load average before and
after is included: the machine may be shared.
"""

from __future__ import annotations

import os
import time
from typing import Any

from ..sweep.executors import LocalExecutor
from ..sweep.options import RunOptions
from ..sweep.run import run_sweep
from ..sweep.signals import stop_on_terminate

__all__ = ["FLAGSHIP_N", "run_suite"]

#: Plausible robots per controller and profile in the flagship analysis.
FLAGSHIP_N = 300
#: Controllers and profiles of the flagship analysis.
FLAGSHIP_ANALYSES = 4
DEFAULT_N = 20
WORKERS = 2


def _load() -> float | None:
    return round(os.getloadavg()[0], 2) if hasattr(os, "getloadavg") else None


def run_suite(steps: int | None = None) -> dict[str, Any]:
    """Episodes/s of the joint method's episodes and its analysis time; see the module
    docstring. ``steps``: plausible robots per profile (default 20)."""
    with stop_on_terminate():
        return _run_suite(steps or DEFAULT_N)


def _run_suite(n: int) -> dict[str, Any]:
    from ..scenario.scenefile import load_scene
    from ..sensitivity.joint import analyse_rows, joint_plan

    scene = load_scene("two-robot-pass")
    plan = joint_plan(scene.name, profiles=["epuck", "epuck-vrep"], controllers=["improved"],
                      seeds=range(n), bins=2 if n < 8 else 4)  # fmt: skip
    out: dict[str, Any] = {
        "scene": scene.name,
        "controller": "improved",
        "profiles": list(plan.profiles),
        "episodes": len(plan),
        "workers": WORKERS,
        "load_average_before": _load(),
    }
    executor = LocalExecutor(WORKERS)
    try:
        executor.start()
        sweep = run_sweep(plan.sweep, scene, RunOptions(executor=executor))
    finally:
        executor.close()
    t0 = time.perf_counter()
    analyses = analyse_rows(sweep.rows, plan.bins)
    analysis_s = (time.perf_counter() - t0) / max(1, len(analyses))
    rate = sweep.ran / sweep.wall_s if sweep.wall_s else 0.0
    flagship = FLAGSHIP_ANALYSES * FLAGSHIP_N
    # the analysis's cost is mostly per number (its regressions and bins), little per
    # episode: at N = 300 it is measured by docs/sweeps.md's --from timing
    estimate = flagship / rate + FLAGSHIP_ANALYSES * analysis_s if rate else None
    out.update(
        wall_s=round(sweep.wall_s, 2),
        episodes_per_s=round(rate, 2),
        analysis_s_per_analysis=round(analysis_s, 3),
        flagship_episodes=flagship,
        flagship_estimate_s=None if estimate is None else round(estimate, 1),
        load_average_after=_load(),
    )
    return out
