"""What runs inside a worker: a batch of episodes, returned as rows.

This module is imported by local worker processes (started with *spawn*, so it must be
importable and do nothing at import time) and by Dask workers (which unpickle
:func:`run_batch` by reference, so ``puckboard`` must be installed there). Each episode
is seeded only by its own spec, so the rows do not depend on which worker ran them, in
which order, or what ran before in the same process.
"""

from __future__ import annotations

import logging
import signal
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from .plan import SCENE_CONTROLLERS, EpisodeSpec
from .rows import error_row, result_row
from .watchdog import call_with_wall_limit

__all__ = ["ignore_interrupts", "run_batch", "run_spec"]

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

    overrides = spec.param_dict
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
    rows it has. It is how a sweep stops work it cannot kill: a task already running on
    a Dask worker cannot be interrupted, but it can decline to start its next episode.
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


def ignore_interrupts() -> None:
    """Worker-process initializer: leave Ctrl-C to the parent.

    A terminal's Ctrl-C reaches every process in the group; the parent decides what to
    keep and stops the workers itself, so they must not die half-way through a result.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
