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
from collections import Counter
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from . import experiment
from .batches import MAX_BATCH, balance_order, make_batches
from .executors import LocalExecutor, SweepExecutor
from .host import Isolation
from .options import DEFAULT_RUN, RunOptions
from .plan import EpisodeSpec, PlanError, SweepPlan, seeds_text
from .progress import NullProgress
from .rows import Outcome
from .signals import Terminated, stops_held
from .summary import GroupSummary, rank_controllers, summarise
from .worker import run_batch

if TYPE_CHECKING:
    from ..scenario.scene import Scene

__all__ = [
    "MAX_BATCH",
    "STOP_GRACE",
    "SweepResult",
    "drain",
    "make_batches",
    "run_sweep",
    "run_sweeps",
]

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

    def error_kinds(self) -> dict[str, int]:
        """How this run's error episodes ended (``error_kind`` → count), most first."""
        kinds = Counter(
            str(r.get("error_kind") or "exception") for r in self.rows if r.get("error")
        )
        return dict(kinds.most_common())

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
    that runs longer; it is recorded as an ``error`` episode of kind ``timeout``. An
    executor that :attr:`~puckboard.sweep.executors.SweepExecutor.stops_processes` (local
    workers) kills the process running it, which stops any layer; elsewhere (in this
    process, on Dask workers that may not start processes) the episode is interrupted from
    within, which stops a layer running Python code but not one blocked in a C call
    (:mod:`puckboard.sweep.watchdog`).
    """
    (result,) = run_sweeps([(plan, scene)], options)
    return result


def run_sweeps(
    parts: Sequence[tuple[SweepPlan, Scene | str | Path]],
    options: RunOptions = DEFAULT_RUN,
    *,
    isolation: Callable[[str], Isolation | None] | None = None,
    aliases: Mapping[str, str] | None = None,
) -> list[SweepResult]:
    """:func:`run_sweep` for several plans, each on its scene, as one stream of tasks on
    one executor and one ``options.store``; a result per plan, in order.

    ``isolation`` maps a controller of the plans to the
    :class:`~puckboard.sweep.host.Isolation` its episodes run in (``None``: shared
    workers), on executors that keep it (local workers): each controller's tasks then
    come together, every plan's in turn, so that a worker serves one controller for as
    long as it can. ``aliases`` maps a controller spec, as the rows name it, to the spec
    the workers load (a submission's version, say, to its file).
    """
    executor, store, progress = options.executor, options.store, options.progress
    batch_size, episode_timeout = options.batch_size, options.episode_timeout
    if episode_timeout is not None and not episode_timeout > 0:
        raise ValueError(f"episode timeout must be positive seconds, got {episode_timeout}")
    scenes = [_loaded(plan, scene) for plan, scene in parts]
    progress = progress or NullProgress()
    results = [SweepResult(plan=plan, outcomes=[]) for plan, _ in parts]
    owner: dict[str, int] = {}  # episode key -> the part it belongs to
    for index, (plan, _) in enumerate(parts):
        for spec in plan.episodes():
            key = spec.key(plan.scenario)
            if key in owner:
                raise PlanError(f"two plans of one run share the episode {key}")
            owner[key] = index
    done: dict[str, Outcome] = {}
    if store is not None:
        for row in store.rows():
            key = str(row.get("key", ""))
            if key in owner:
                done[key] = Outcome.from_row(row)
    for key, outcome in done.items():
        results[owner[key]].outcomes.append(outcome)
        results[owner[key]].skipped += 1
    log.info("sweep: %d episodes planned, %d already done", len(owner), len(done))

    own_executor = executor is None
    executor = executor or LocalExecutor()
    t0 = time.perf_counter()
    progress.start(len(owner), len(done))

    def collect(rows: list[dict[str, Any]]) -> None:
        # one step a stop cannot cut in two: the rows stored and the rows counted stay one
        # number, which the message after Ctrl-C or SIGTERM states as what was kept
        with stops_held():
            if store is not None:
                store.append(rows)
            for row in rows:
                result = results[owner[str(row["key"])]]
                result.rows.append(row)
                result.outcomes.append(Outcome.from_row(row))
                result.ran += 1
        progress.advance(len(rows))

    todo = [[s for s in plan.episodes() if s.key(plan.scenario) not in done] for plan, _ in parts]
    try:
        stopped = None
        if any(todo):
            stopped = drain(
                executor,
                lambda: _start(
                    executor, parts, scenes, todo, batch_size, episode_timeout, isolation, aliases
                ),
                collect,
            )
        if stopped is not None:
            for result in results:
                result.interrupted = True
                result.terminated = isinstance(stopped, Terminated)
            log.info(
                "sweep interrupted: %d episodes finished in this run", sum(r.ran for r in results)
            )
    finally:
        progress.close()
        if store is not None:
            store.flush()
        if own_executor:
            executor.close()
        for result in results:
            result.wall_s = time.perf_counter() - t0
    return results


def _loaded(plan: SweepPlan, scene: Scene | str | Path) -> Scene:
    if isinstance(scene, (str, Path)):  # a Scene (or anything with its fields) is used as is
        from ..scenario.scenefile import load_scene

        scene = load_scene(scene)
    if scene.name != plan.scenario:
        raise PlanError(f"the plan is for scenario {plan.scenario!r}, the scene is {scene.name!r}")
    return scene


def _start(
    executor: SweepExecutor,
    parts: Sequence[tuple[SweepPlan, Any]],
    scenes: Sequence[Scene],
    todo: Sequence[Sequence[EpisodeSpec]],
    batch_size: int | None,
    episode_timeout: float | None,
    isolation: Callable[[str], Isolation | None] | None,
    aliases: Mapping[str, str] | None,
) -> Iterator[list[dict[str, Any]]]:
    """Cut the episodes to run into batches, in the order :func:`run_sweeps` promises,
    and hand them to ``executor``; returns the stream of their rows."""
    controllers = list(dict.fromkeys(c for plan, _ in parts for c in plan.controllers))
    given = dict(aliases or {})
    loadable = {c: executor.runnable_controller(given.get(c, c)) for c in controllers}
    loadable = {c: a for c, a in loadable.items() if a != c}
    ordered: list[tuple[int, EpisodeSpec]] = []
    if isolation is None:  # part after part, each longest first
        for index, specs in enumerate(todo):
            ordered += [(index, s) for s in balance_order(specs, scenes[index])]
    else:  # controller after controller, each on every part
        for controller in controllers:
            for index, specs in enumerate(todo):
                mine = [s for s in specs if s.controller == controller]
                ordered += [(index, s) for s in balance_order(mine, scenes[index])]
    bounds = [(i, s.controller if isolation else "") for i, s in ordered]
    cuts = make_batches([s for _, s in ordered], executor.workers, batch_size, bounds)
    # per-episode warnings only when asked for more output (puckboard -v)
    level = logging.WARNING if log.isEnabledFor(logging.INFO) else logging.ERROR
    stop = executor.stop_flag()
    # the limit on the process where the executor can kill it, else in the episode
    on_process = executor.stops_processes and episode_timeout is not None
    inside = None if on_process else episode_timeout
    tasks = []
    isolations: list[Isolation | None] = []
    first = 0
    for batch in cuts:
        index = ordered[first][0]
        first += len(batch)
        tasks.append(
            (scenes[index], parts[index][0].scenario, batch, loadable, level, inside, stop)
        )
        isolations.append(isolation(batch[0].controller) if isolation else None)
    extra: dict[str, Any] = {"unit_limit": episode_timeout} if on_process else {}
    if isolation is not None:
        extra["isolation"] = isolations
    return executor.run(run_batch, tasks, **extra)


def drain(
    executor: SweepExecutor,
    start: Callable[[], Iterator[Any]],
    collect: Callable[[Any], None],
) -> KeyboardInterrupt | None:
    """Hand each result of the stream ``start()`` opens on ``executor`` to ``collect``.

    On Ctrl-C (or SIGTERM, :class:`~puckboard.sweep.signals.Terminated`) the tasks not
    started are dropped, the running ones end after their current unit and what they
    finish within :data:`STOP_GRACE` seconds is collected too; the interrupt is then
    returned (``None`` when every task ran), for the caller to say what it kept.
    """
    stream: Iterator[Any] | None = None
    try:
        stream = start()
        for value in stream:
            collect(value)
    except KeyboardInterrupt as exc:
        _keep_what_finishes(executor, collect)
        return exc
    finally:
        _close(stream)
    return None


def _keep_what_finishes(executor: SweepExecutor, collect: Callable[[Any], None]) -> None:
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
