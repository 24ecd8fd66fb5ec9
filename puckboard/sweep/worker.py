"""What runs inside a worker: a batch of episodes, returned as rows.

This module is imported by local worker processes (hosts, :mod:`puckboard.sweep.host`;
started with *spawn*, so it must be importable and do nothing at import time) and by Dask
workers (which unpickle :func:`run_batch` by reference, so ``puckboard`` must be
installed there). Each episode is seeded only by its own spec, so the rows do not depend
on which worker ran them, in which order, or what ran before in the same process.

A batch reports each episode as a *unit* (:func:`report_unit_began`,
:func:`report_unit_done`) to whoever runs it: in a host, the parent, which can then stop
an episode that runs past its wall-clock limit by killing the process, and run the rest
of the batch elsewhere (``start`` and ``lost`` of :func:`run_batch`). Elsewhere the
reports go nowhere.
"""

from __future__ import annotations

import contextlib
import logging
import os
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol

from .plan import SCENE_CONTROLLERS, EpisodeSpec, episode_overrides
from .rows import error_row, result_row
from .watchdog import call_with_wall_limit

if TYPE_CHECKING:
    from multiprocessing.synchronize import Event

    from ..scenario.scene import Scene

__all__ = [
    "EpisodeLost",
    "LocalStopFlag",
    "bind_stop_event",
    "mark_ready",
    "quieter_logs",
    "report_unit_began",
    "report_unit_done",
    "run_batch",
    "run_spec",
    "set_unit_reporter",
    "worker_ready",
]

log = logging.getLogger(__name__)


class EpisodeLost(Exception):
    """An episode that ended without a result because its process was stopped or died.

    ``kind`` is the error row's ``error_kind`` (:data:`~puckboard.sweep.rows.ERROR_KINDS`):
    ``timeout`` (stopped at its wall-clock limit), ``exited`` (the process exited during
    it) or ``crashed`` (the process was killed or crashed).
    """

    def __init__(self, kind: str, message: str) -> None:
        super().__init__(message)
        self.kind = kind

    def __reduce__(self) -> tuple[Any, ...]:
        return (EpisodeLost, (self.kind, str(self)))


@dataclass(frozen=True)
class LostUnit:
    """Why the unit a task is run again from was lost (see :func:`run_batch`)."""

    kind: str
    message: str


class UnitReporter(Protocol):
    def began(self, index: int) -> None: ...
    def done(self, index: int, value: Any) -> None: ...


#: Where this process's unit reports go (set by a host; ``None``: nowhere).
_reporter: UnitReporter | None = None


def set_unit_reporter(reporter: UnitReporter | None) -> None:
    """Send this process's unit reports to ``reporter`` (a host's pipe to its parent)."""
    global _reporter
    _reporter = reporter


def report_unit_began(index: int) -> None:
    """Unit ``index`` of the running task starts now (its wall-clock limit starts too)."""
    if _reporter is not None:
        _reporter.began(index)


def report_unit_done(index: int, value: Any) -> None:
    """Unit ``index`` of the running task has finished with ``value``."""
    if _reporter is not None:
        _reporter.done(index, value)


def run_spec(
    scene: Scene,
    scenario: str,
    spec: EpisodeSpec,
    aliases: Mapping[str, str] | None = None,
    wall_limit: float | None = None,
) -> dict[str, Any]:
    """Run one episode and flatten its result; an exception becomes an ``error`` row.

    ``aliases`` maps a controller spec to the spec this worker can load it by (a file
    uploaded to a remote Dask worker is imported by module name); rows always carry the
    spec as the user gave it, so they identify the episode the same way everywhere.
    ``wall_limit`` (s of wall-clock time) stops an episode that runs away; it becomes an
    ``error`` row like any other exception.
    """
    from ..control.episode import run_episode

    overrides = episode_overrides(spec.param_dict)
    duration = overrides.pop("duration", None)
    loadable = (aliases or {}).get(spec.controller, spec.controller)
    controller = None if loadable == SCENE_CONTROLLERS else loadable
    try:
        result = call_with_wall_limit(
            lambda: run_episode(
                scene,
                controller=controller,
                seed=spec.seed,
                duration=duration,
                overrides=overrides or None,
            ),
            wall_limit,
        )
    except (Exception, SystemExit) as exc:  # a controller calling sys.exit() is its failure
        # Reported once by the driver from the rows' ``error`` column, not per worker.
        log.debug("episode %s raised", spec, exc_info=True)
        return error_row(scenario, spec, exc)
    return result_row(scenario, spec, result.to_dict())


def run_batch(
    scene: Scene,
    scenario: str,
    specs: Sequence[EpisodeSpec],
    aliases: Mapping[str, str] | None = None,
    log_level: int = logging.ERROR,
    wall_limit: float | None = None,
    stop: Callable[[], bool] | None = None,
    *,
    start: int = 0,
    lost: LostUnit | None = None,
) -> list[dict[str, Any]]:
    """Run ``specs`` one after the other in this process and return their rows.

    puckboard's own log messages below ``log_level`` are dropped while the batch runs:
    a warning a single run shows once (a clamped wheel command, say) would otherwise be
    printed by every episode of the sweep.

    ``stop`` is asked before each episode; once it answers true the batch ends with the
    rows it has. It is how a stopped sweep keeps what running batches finished (the
    local pool's :class:`LocalStopFlag`) and frees workers it cannot kill (a task
    already running on a Dask worker cannot be interrupted, but it can decline to start
    its next episode).

    Each episode is reported as a unit (its index in ``specs``). ``start`` skips the
    episodes before it (their rows are the caller's already) and ``lost`` says why
    episode ``start`` was lost when it ran before: it becomes an error row of that kind
    without running again, and the batch goes on from the next one. Rows are returned
    from ``start`` on.
    """
    rows: list[dict[str, Any]] = []
    with quieter_logs(log_level):
        for index in range(start, len(specs)):
            spec = specs[index]
            if lost is not None and index == start:
                row = error_row(scenario, spec, EpisodeLost(lost.kind, lost.message))
            else:
                if stop is not None and stop():
                    log.info("batch stopped after %d of %d episodes", len(rows), len(specs))
                    break
                report_unit_began(index)
                row = run_spec(scene, scenario, spec, aliases, wall_limit)
            rows.append(row)
            report_unit_done(index, row)
        return rows


@contextlib.contextmanager
def quieter_logs(level: int = logging.ERROR) -> Iterator[None]:
    """puckboard's own log messages below ``level`` dropped within the block: a warning a
    single run shows once (a clamped wheel command, say) would otherwise be printed by
    every episode a worker runs."""
    logger = logging.getLogger("puckboard")
    previous = logger.level
    logger.setLevel(max(previous, level))
    try:
        yield
    finally:
        logger.setLevel(previous)


#: The stop event of this worker's pool, set by :func:`bind_stop_event`.
_stop_event: Any = None
#: ``time.monotonic()`` when this worker had started up (start-up measurements).
_ready_at: float | None = None


class LocalStopFlag:
    """The stop flag of a local pool's batches: has the parent set the pool's event?

    Picklable and stateless: the event itself reached the worker once, when the process
    was created (a multiprocessing event can travel no other way).
    """

    def __call__(self) -> bool:
        return _stop_event is not None and bool(_stop_event.is_set())


def bind_stop_event(stop_event: Event) -> None:
    """Keep the pool's ``stop_event`` for :class:`LocalStopFlag` (a host, at its start)."""
    global _stop_event
    _stop_event = stop_event


def mark_ready() -> None:
    """Note that this worker has started up: imported what an episode needs."""
    global _ready_at
    _ready_at = time.monotonic()


def worker_ready() -> tuple[int, float | None]:
    """This worker's process id and when it was ready (``time.monotonic()``, a clock
    shared by the processes of one machine): a task for measuring start-up."""
    return os.getpid(), _ready_at
