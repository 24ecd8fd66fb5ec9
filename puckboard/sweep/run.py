"""Run a sweep: skip what the output file already holds, batch the rest, collect rows.

:func:`run_sweep` is the whole pipeline the ``puckboard sweep`` command uses::

    plan --(minus rows already in --out)--> batches --executor--> rows --> store, summary

Episodes go longest first, in batches that shrink to single episodes at the end
(:mod:`puckboard.sweep.batches`), so that workers finish together. Rows are written as
each batch finishes. On Ctrl-C (or SIGTERM, see :mod:`puckboard.sweep.signals`) batches
not started are dropped, running ones end after their current episode and hand back
what they finished, and what is still running after :data:`STOP_GRACE` seconds is
stopped; every finished row stays in the file, and the next run resumes from there.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from . import experiment
from .batches import MAX_BATCH, balance_order, make_batches
from .executors import LocalExecutor, SweepExecutor
from .options import DEFAULT_RUN, RunOptions
from .plan import PlanError, SweepPlan, seeds_text
from .progress import NullProgress
from .rows import Outcome
from .signals import Terminated
from .summary import GroupSummary, rank_controllers, summarise
from .worker import run_batch

if TYPE_CHECKING:
    from ..scenario.scene import Scene

__all__ = ["MAX_BATCH", "STOP_GRACE", "SweepResult", "make_batches", "run_sweep"]

log = logging.getLogger(__name__)

#: Seconds a stopped sweep waits for running batches to finish their current episode.
STOP_GRACE = 2.0


@dataclass
class SweepResult:
    """What a sweep produced: every outcome of the plan (old and new) and how it went."""

    plan: SweepPlan
    outcomes: list[Outcome]
    rows: list[dict[str, Any]] = field(default_factory=list)
    ran: int = 0
    skipped: int = 0
    interrupted: bool = False
    #: Stopped by SIGTERM rather than Ctrl-C (``interrupted`` is true as well).
    terminated: bool = False
    wall_s: float = 0.0

    @property
    def errors(self) -> list[str]:
        """``error`` messages of this run's episodes that raised (one per episode)."""
        return [str(r["error"]) for r in self.rows if r.get("error")]

    def groups(self) -> list[GroupSummary]:
        order = {c: i for i, c in enumerate(self.plan.controllers)}
        groups = summarise(self.outcomes)
        combos = [dict(sorted(c.items())) for c in self.plan.combinations()]

        def position(g: GroupSummary) -> tuple[int, int]:
            combo = dict(sorted(g.params.items()))
            return order.get(g.controller, len(order)), (
                combos.index(combo) if combo in combos else len(combos)
            )

        return sorted(groups, key=position)

    def ranking(self) -> list[GroupSummary]:
        return rank_controllers(self.outcomes)

    # a sweep counts, times and heads itself as every experiment's run does (.experiment)
    def counts(self) -> dict[str, Any]:
        """:func:`puckboard.sweep.experiment.counts` of this run."""
        return experiment.counts(self)

    @property
    def episodes_per_s(self) -> float:
        """Episodes this run ran per wall-clock second (0 when none ran)."""
        return experiment.episodes_per_s(self)

    def episodes_text(self, stored: str | None = None) -> str:
        """:func:`puckboard.sweep.experiment.episodes_text` of this run."""
        return experiment.episodes_text(self, stored)

    def to_dict(self) -> dict[str, Any]:
        """The ``--json`` object: counts, the plan, ``groups`` and ``ranking``."""
        return {
            "scenario": self.plan.scenario,
            "episodes": len(self.outcomes),
            **self.counts(),
            "controllers": list(self.plan.controllers),
            "seeds": seeds_text(self.plan.seeds),
            "parameters": {k: list(v) for k, v in self.plan.grid.items()},
            "fixed": dict(self.plan.fixed),
            "groups": [g.to_dict() for g in self.groups()],
            "ranking": [g.to_dict() for g in self.ranking()],
        }


def run_sweep(
    plan: SweepPlan, scene: Scene | str | Path, options: RunOptions = DEFAULT_RUN
) -> SweepResult:
    """Run every episode of ``plan`` on ``scene`` that ``options.store`` does not hold yet.

    ``scene`` is a :class:`~puckboard.scenario.scene.Scene`, a shipped scene name or a scene
    file; it is loaded here once and sent to the workers, so remote Dask workers do not
    need the file. Without ``options.executor`` a :class:`LocalExecutor` on all cores is
    used (and shut down afterwards). Ctrl-C stops the sweep and returns what finished with
    ``interrupted=True``. ``options.episode_timeout`` (wall-clock seconds) ends an episode
    whose controller never returns; it is recorded as an ``error`` episode.
    """
    executor, store, progress = options.executor, options.store, options.progress
    batch_size, episode_timeout = options.batch_size, options.episode_timeout
    if episode_timeout is not None and not episode_timeout > 0:
        raise ValueError(f"episode timeout must be positive seconds, got {episode_timeout}")
    if isinstance(scene, (str, Path)):  # a Scene (or anything with its fields) is used as is
        from ..scenario.scenefile import load_scene

        scene = load_scene(scene)
    if scene.name != plan.scenario:
        raise PlanError(f"the plan is for scenario {plan.scenario!r}, the scene is {scene.name!r}")
    progress = progress or NullProgress()
    planned = list(plan.episodes())
    wanted = {spec.key(plan.scenario): spec for spec in planned}
    done: dict[str, Outcome] = {}
    if store is not None:
        for row in store.rows():
            key = str(row.get("key", ""))
            if key in wanted:
                done[key] = Outcome.from_row(row)
    todo = [spec for spec in planned if spec.key(plan.scenario) not in done]
    result = SweepResult(plan=plan, outcomes=list(done.values()), skipped=len(done))
    log.info("sweep: %d episodes planned, %d already done", len(planned), len(done))

    own_executor = executor is None
    executor = executor or LocalExecutor()
    t0 = time.perf_counter()
    progress.start(len(planned), len(done))

    def collect(rows: list[dict[str, Any]]) -> None:
        if store is not None:
            store.append(rows)
        result.rows.extend(rows)
        result.outcomes.extend(Outcome.from_row(r) for r in rows)
        result.ran += len(rows)
        progress.advance(len(rows))

    stream: Iterator[list[dict[str, Any]]] | None = None
    try:
        if todo:
            aliases = {c: executor.runnable_controller(c) for c in plan.controllers}
            aliases = {c: a for c, a in aliases.items() if a != c}
            batches = make_batches(balance_order(todo, scene), executor.workers, batch_size)
            # per-episode warnings only when asked for more output (puckboard -v)
            level = logging.WARNING if log.isEnabledFor(logging.INFO) else logging.ERROR
            stop = executor.stop_flag()
            tasks = [
                (scene, plan.scenario, batch, aliases, level, episode_timeout, stop)
                for batch in batches
            ]
            stream = executor.run(run_batch, tasks)
            for rows in stream:
                collect(rows)
    except KeyboardInterrupt as exc:
        result.interrupted = True
        result.terminated = isinstance(exc, Terminated)
        _keep_what_finishes(executor, collect)
        log.info("sweep interrupted: %d episodes finished in this run", result.ran)
    finally:
        _close(stream)
        progress.close()
        if store is not None:
            store.flush()
        if own_executor:
            executor.close()
        result.wall_s = time.perf_counter() - t0
    return result


def _keep_what_finishes(
    executor: SweepExecutor, collect: Callable[[list[dict[str, Any]]], None]
) -> None:
    """After Ctrl-C: keep the rows of batches that end within :data:`STOP_GRACE` s (each
    ends after its current episode), then stop the rest; a second Ctrl-C stops at once."""
    stopping = executor.stop(STOP_GRACE)
    try:
        for rows in stopping:
            collect(rows)
    except KeyboardInterrupt:
        log.info("interrupted again: not waiting for running episodes")
    finally:
        _close(stopping)
        executor.cancel()


def _close(iterator: Iterator[Any] | None) -> None:
    """Close a generator now rather than whenever it is collected: an executor's
    generator cancels its tasks when closed early."""
    close = getattr(iterator, "close", None)
    if close is not None:
        close()
