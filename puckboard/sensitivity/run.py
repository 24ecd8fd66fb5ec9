"""Run a sensitivity analysis on the sweep machinery and summarise it.

Nothing here is particular about how episodes run: the analysis's points are a
:class:`~puckboard.sweep.SweepPlan`, so :func:`~puckboard.sweep.run_sweep` skips what
``--out`` already holds, balances batches over local processes or a Dask cluster, shows
progress and keeps every finished row on Ctrl-C; an interrupted analysis is summarised
from what ran, and the same command resumes it.
"""

from __future__ import annotations

from typing import Any

from ..sweep.executors import SweepExecutor
from ..sweep.progress import Progress
from ..sweep.run import run_sweep
from ..sweep.store import ResultStore
from .plan import SensitivityPlan
from .summary import SensitivityResult

__all__ = ["run_sensitivity"]


def run_sensitivity(
    plan: SensitivityPlan,
    scene: Any,
    *,
    executor: SweepExecutor | None = None,
    store: ResultStore | None = None,
    batch_size: int | None = None,
    progress: Progress | None = None,
    episode_timeout: float | None = None,
) -> SensitivityResult:
    """Run every episode of ``plan`` not yet in ``store`` (see
    :func:`~puckboard.sweep.run_sweep` for the arguments) and summarise all of them."""
    sweep = run_sweep(
        plan.sweep,
        scene,
        executor=executor,
        store=store,
        batch_size=batch_size,
        progress=progress,
        episode_timeout=episode_timeout,
    )
    return SensitivityResult.of(plan, sweep)
