"""Run a transfer report on the sweep machinery, one scene's sweep after another.

:func:`run_transfer` is the report as ``puckboard transfer`` makes it, from the names it
takes (scenes, controllers, profiles, seeds, families, fixed parameters), returning the
:class:`~puckboard.transfer.result.TransferResult` the command prints
(:func:`~puckboard.transfer.report.format_result`)::

    from puckboard.transfer import format_result, run_transfer
    result = run_transfer("two-robot-pass", controllers=["robust"], families=["noise"])
    print(format_result(result))

:func:`run_transfer_plan` runs a plan already made (:func:`~.plan.transfer_plan`).

Each sweep of the plan (:meth:`TransferPlan.sweeps`) goes through
:func:`~puckboard.sweep.run_sweep` on one executor: rows already in ``--out`` are skipped,
batches are balanced over local processes or a Dask cluster, and Ctrl-C keeps every
finished row. One progress display covers the whole report, so its time left is the
report's, not one scene's. After an interrupt no further sweep starts; the report is
summarised from what ran, and the same command resumes it.
"""

from __future__ import annotations

import json
import time
from collections.abc import Iterable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

from ..sweep.executors import LocalExecutor
from ..sweep.options import DEFAULT_RUN, RunOptions
from ..sweep.plan import params_key
from ..sweep.progress import NullProgress, Progress
from ..sweep.run import SweepResult, run_sweep
from ..sweep.store import ResultStore
from .plan import DEFAULT_SEEDS, TransferPlan, plan_from_names
from .result import TransferResult

if TYPE_CHECKING:
    from ..profile import RobotProfile
    from ..scenario.scene import Scene
    from ..sweep.plan import SweepPlan

__all__ = ["run_transfer", "run_transfer_plan"]


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


class _Labelled(ResultStore):
    """The report's ``--out`` store, each row written with the models it belongs to:
    ``family`` and ``model`` (``noise ×2``), several joined by ``; `` where models share
    their episodes (a noise family's scale 1 is the design model)."""

    def __init__(self, store: ResultStore, labels: Mapping[str, tuple[str, str]]) -> None:
        super().__init__(store.path)
        self._store = store
        self._labels = labels

    def rows(self) -> list[dict[str, Any]]:
        return self._store.rows()

    def keys(self) -> set[str]:
        return self._store.keys()

    def append(self, rows: Iterable[Mapping[str, Any]]) -> None:
        self._store.append(self._labelled(row) for row in rows)

    def _labelled(self, row: Mapping[str, Any]) -> dict[str, Any]:
        try:
            found = json.loads(str(row.get("key", "")))
            family, model = self._labels.get(params_key(found["params"]), ("", ""))
        except (ValueError, KeyError, TypeError):
            family, model = "", ""
        return {**row, "family": family, "model": model}

    def flush(self) -> None:
        self._store.flush()

    def close(self) -> None:
        self._store.close()


def _labels(plan: TransferPlan) -> dict[str, tuple[str, str]]:
    """Each point's parameters (as episodes carry them) → its families and models."""
    found: dict[str, tuple[list[str], list[str]]] = {}
    for point in plan.points:
        dt = (plan.dts or {}).get(point.scene, 0.0)
        family = next((f for f in plan.families if f.name == point.family), None)
        model = point.family if family is None else family.label(dt)
        if family is not None and family.moves:
            model = f"{family.name} {family.scale_text(point.scale, dt)}"
        families, models = found.setdefault(plan.point_key(point), ([], []))
        for names, name in ((families, point.family), (models, model)):
            if name not in names:
                names.append(name)
    return {k: ("; ".join(f), "; ".join(m)) for k, (f, m) in found.items()}


def _already_done(plan: TransferPlan, store: ResultStore | None) -> int:
    if store is None:
        return 0
    keys = store.keys()
    return sum(
        1 for sweep in plan.sweeps for spec in sweep.episodes() if spec.key(sweep.scenario) in keys
    )


def run_transfer(
    scenes: Sequence[str | Scene] | str | Scene,
    *,
    controllers: Sequence[str] = (),
    profiles: Sequence[str | RobotProfile] = (),
    seeds: range | str = DEFAULT_SEEDS,
    families: Sequence[str] | None = None,
    fixed: Mapping[str, Any] | None = None,
    options: RunOptions = DEFAULT_RUN,
) -> TransferResult:
    """The transfer report ``puckboard transfer`` prints, from the names it takes.

    ``scenes``: shipped names, scene files or loaded scenes; ``controllers``: specs
    (default: each robot's from its scene); ``profiles``: shipped names, profile files or
    profiles (default: each scene's); ``seeds``: a range or ``A:B`` (default
    :data:`~puckboard.transfer.plan.DEFAULT_SEEDS`); ``families``: names (default: all);
    ``fixed``: parameters every model shares. Checked before anything runs (a one-line
    ``ValueError``); ``options`` says where and how the episodes run.
    """
    plan, loaded = plan_from_names(
        scenes, controllers=controllers, profiles=profiles, seeds=seeds, families=families,
        fixed=fixed,
    )  # fmt: skip
    return run_transfer_plan(plan, loaded, options)


def run_transfer_plan(
    plan: TransferPlan, scenes: Mapping[str, Scene], options: RunOptions = DEFAULT_RUN
) -> TransferResult:
    """Run every episode of ``plan`` not yet in ``options.store`` and summarise all of them.

    ``scenes`` holds each scene the plan's sweeps run on, loaded, by name. Without an
    executor a :class:`~puckboard.sweep.LocalExecutor` on all cores is used (and closed
    afterwards). Rows written to the store carry the ``family`` and ``model`` of their
    episodes. See :func:`~puckboard.sweep.run_sweep` for the rest.
    """
    progress = options.progress or NullProgress()
    own_executor = options.executor is None
    executor = options.executor or LocalExecutor()
    store = options.store
    labelled = None if store is None else _Labelled(store, _labels(plan))
    each = RunOptions(
        executor=executor,
        store=labelled,
        batch_size=options.batch_size,
        progress=_Within(progress),
        episode_timeout=options.episode_timeout,
    )
    t0 = time.perf_counter()
    sweeps: list[SweepResult] = []
    stopped: KeyboardInterrupt | None = None
    progress.start(len(plan), _already_done(plan, store))
    try:
        for sweep in plan.sweeps:
            ran = run_sweep(sweep, scenes[sweep.scenario], each)
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
