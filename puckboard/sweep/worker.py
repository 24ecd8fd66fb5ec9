"""What runs inside a worker: a batch of episodes, returned as rows.

This module is imported by local worker processes (started with *spawn*, so it must be
importable and do nothing at import time) and by Dask workers (which unpickle
:func:`run_batch` by reference, so ``puckboard`` must be installed there). Each episode
is seeded only by its own spec, so the rows do not depend on which worker ran them, in
which order, or what ran before in the same process.
"""

from __future__ import annotations

import logging
import os
import signal
import threading
import time
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from .plan import SCENE_CONTROLLERS, EpisodeSpec, episode_overrides
from .rows import error_row, result_row
from .watchdog import call_with_wall_limit

__all__ = ["LocalStopFlag", "init_local_worker", "run_batch", "run_spec", "worker_ready"]

log = logging.getLogger(__name__)


def run_spec(
    scene: Any,
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
    scene: Any,
    scenario: str,
    specs: Sequence[EpisodeSpec],
    aliases: Mapping[str, str] | None = None,
    log_level: int = logging.ERROR,
    wall_limit: float | None = None,
    stop: Callable[[], bool] | None = None,
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
    """
    logger = logging.getLogger("puckboard")
    previous = logger.level
    logger.setLevel(max(previous, log_level))
    rows: list[dict[str, Any]] = []
    try:
        for spec in specs:
            if stop is not None and stop():
                log.info("batch stopped after %d of %d episodes", len(rows), len(specs))
                break
            rows.append(run_spec(scene, scenario, spec, aliases, wall_limit))
        return rows
    finally:
        logger.setLevel(previous)


#: The stop event of this worker's pool, set by :func:`init_local_worker`.
_stop_event: Any = None
#: ``time.monotonic()`` when :func:`init_local_worker` had finished (start-up measurements).
_ready_at: float | None = None


class LocalStopFlag:
    """The stop flag of a local pool's batches: has the parent set the pool's event?

    Picklable and stateless: the event itself reached the worker once, when the process
    was created (a multiprocessing event can travel no other way).
    """

    def __call__(self) -> bool:
        return _stop_event is not None and bool(_stop_event.is_set())


def init_local_worker(parent_alive: Any, stop_event: Any) -> None:
    """Initializer of a local worker process.

    * Ignore Ctrl-C: it reaches every process of the terminal's group, but the parent
      decides what to keep and stops the workers itself (on POSIX the process was
      created with SIGINT ignored already, see :mod:`puckboard.sweep.signals`).
    * Exit when the parent is gone: ``parent_alive`` is the reading end of a pipe the
      parent holds open and never writes to, so it reports end-of-file once the parent
      has exited, however it ended (SIGKILL included). A worker left waiting for tasks
      from a dead parent would otherwise live on.
    * Keep ``stop_event`` for :class:`LocalStopFlag`.
    * Import what an episode needs now, while the pool starts, not in the first task.
    """
    global _stop_event, _ready_at
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _stop_event = stop_event

    def exit_with_parent() -> None:
        try:
            while True:
                parent_alive.recv()  # nothing is ever sent: returns only at end-of-file
        except (EOFError, OSError):
            os._exit(1)

    threading.Thread(target=exit_with_parent, name="puckboard-parent-watch", daemon=True).start()
    from ..control import episode  # noqa: F401

    _ready_at = time.monotonic()


def worker_ready() -> tuple[int, float | None]:
    """This worker's process id and when it was ready (``time.monotonic()``, a clock
    shared by the processes of one machine): a task for measuring start-up."""
    return os.getpid(), _ready_at
