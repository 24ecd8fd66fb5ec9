"""Run a transfer report on the sweep machinery, one scene's sweep after another.

Each sweep of the plan (:meth:`TransferPlan.sweeps`) goes through
:func:`~puckboard.sweep.run_sweep` on one executor: rows already in ``--out`` are skipped,
batches are balanced over local processes or a Dask cluster, and Ctrl-C keeps every
finished row. One progress display covers the whole report, so its time left is the
report's, not one scene's. After an interrupt no further sweep starts; the report is
summarised from what ran, and the same command resumes it.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from typing import TYPE_CHECKING

from ..sweep.executors import LocalExecutor, SweepExecutor
from ..sweep.progress import NullProgress, Progress
from ..sweep.run import SweepResult, run_sweep
from ..sweep.store import ResultStore
from .plan import TransferPlan
from .result import TransferResult

if TYPE_CHECKING:
    from ..scenario.scene import Scene
    from ..sweep.plan import SweepPlan

__all__ = ["run_transfer"]


class _Within:
    """One sweep's view of the report's progress: its advances count, its start and
    close do not (the report starts the display once, with every sweep's total)."""

    def __init__(self, progress: Progress) -> None:
        self._progress = progress

    def start(self, total: int, done: int = 0) -> None:
        pass

    def advance(self, n: int) -> None:
        self._progress.advance(n)

    def close(self) -> None:
        pass


def _already_done(plan: TransferPlan, store: ResultStore | None) -> int:
    if store is None:
        return 0
    keys = store.keys()
    return sum(
        1 for sweep in plan.sweeps for spec in sweep.episodes() if spec.key(sweep.scenario) in keys
    )


def run_transfer(
    plan: TransferPlan,
    scenes: Mapping[str, Scene],
    *,
    executor: SweepExecutor | None = None,
    store: ResultStore | None = None,
    batch_size: int | None = None,
    progress: Progress | None = None,
    episode_timeout: float | None = None,
) -> TransferResult:
    """Run every episode of ``plan`` not yet in ``store`` and summarise all of them.

    ``scenes`` holds each scene the plan's sweeps run on, loaded, by name. Without
    ``executor`` a :class:`~puckboard.sweep.LocalExecutor` on all cores is used (and
    closed afterwards). See :func:`~puckboard.sweep.run_sweep` for the other arguments.
    """
    progress = progress or NullProgress()
    own_executor = executor is None
    executor = executor or LocalExecutor()
    t0 = time.perf_counter()
    sweeps: list[SweepResult] = []
    stopped: KeyboardInterrupt | None = None
    progress.start(len(plan), _already_done(plan, store))
    try:
        for sweep in plan.sweeps:
            ran = run_sweep(
                sweep,
                scenes[sweep.scenario],
                executor=executor,
                store=store,
                batch_size=batch_size,
                progress=_Within(progress),
                episode_timeout=episode_timeout,
            )
            sweeps.append(ran)
            if ran.interrupted:
                break
    except KeyboardInterrupt as exc:  # between two sweeps: what ran is in their results
        stopped = exc
    finally:
        progress.close()
        if own_executor:
            executor.close()
    for sweep in plan.sweeps[len(sweeps) :]:  # not started: what --out holds of them
        sweeps.append(_from_store(sweep, store))
    result = TransferResult.of(plan, sweeps, time.perf_counter() - t0)
    if stopped is not None:
        from ..sweep.signals import Terminated

        result.stopped = True
        result.stopped_by_terminate = isinstance(stopped, Terminated)
    return result


def _from_store(sweep: SweepPlan, store: ResultStore | None) -> SweepResult:
    """A sweep that did not start (the report was stopped first), from the rows ``store``
    already holds of it."""
    from ..sweep.rows import Outcome

    wanted = {spec.key(sweep.scenario) for spec in sweep.episodes()}
    rows = [] if store is None else [r for r in store.rows() if str(r.get("key")) in wanted]
    outcomes = list({str(r["key"]): Outcome.from_row(r) for r in rows}.values())
    return SweepResult(plan=sweep, outcomes=outcomes, skipped=len(outcomes))
