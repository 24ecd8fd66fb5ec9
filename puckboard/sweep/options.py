"""Where and how an experiment's episodes run: one options object for every experiment.

A sweep, a sensitivity analysis (either method), a transfer report and a tuning study
all run their episodes on the sweep machinery, and each is asked the same things: on
which executor, appending to which ``--out`` store, in batches of what size, showing
what progress, stopping an episode after how long. :class:`RunOptions` says them once,
so each experiment's run function takes its plan, its scene and one ``options``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .executors import SweepExecutor
    from .progress import Progress
    from .store import ResultStore

__all__ = ["DEFAULT_RUN", "RunOptions"]


@dataclass(frozen=True)
class RunOptions:
    """How an experiment's episodes run (every field optional).

    ``executor``: where (default: a :class:`~puckboard.sweep.LocalExecutor` on every
    core, made and closed by the run); ``store``: the ``--out`` rows, skipped when there
    and appended as episodes finish; ``batch_size``: episodes per task (default:
    automatic); ``progress``: the display (default: none); ``episode_timeout``:
    wall-clock seconds after which an episode counts as ``error``.
    """

    executor: SweepExecutor | None = None
    store: ResultStore | None = None
    batch_size: int | None = None
    progress: Progress | None = None
    episode_timeout: float | None = None


#: The options of a run given none: every core, no store, no progress, no time limit.
DEFAULT_RUN = RunOptions()
