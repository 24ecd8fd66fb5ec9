"""How a sweep's episodes become tasks: in which order, and how many per task.

Executors hand tasks, in the order given, to whichever worker is free (a process pool and
Dask both do). What a sweep loses to that is the end: workers that have run out of tasks
wait for the last ones. Episodes differ in length — the judge stops one as soon as its
verdict is final, so a collision at 5 s ends long before a success at 120 s — and how
long the last tasks run decides how long the others wait. Two choices keep that wait
short (``docs/sweeps.md`` has the measurements and the model behind them):

* :func:`balance_order` puts the episodes that may run longest first (by their step
  limit, ``duration / dt``), and within equal limits takes one episode of every
  controller × parameter group in turn (seed by seed). In plan order a group whose
  episodes all run long (a profile that succeeds, so runs to the end) would come last,
  and the end of the sweep would be nothing but long episodes.
* :func:`make_batches` makes tasks that shrink as the sweep advances ("guided
  self-scheduling", Polychronopoulos & Kuck 1987): several episodes per task at first,
  where they amortise the per-task cost (pickling the scene, a round trip to the
  scheduler), and single episodes at the end, so no worker ends on a long batch.

Neither changes a result: every episode is seeded by its own spec alone.
"""

from __future__ import annotations

import math
from collections.abc import Hashable, Sequence
from typing import TYPE_CHECKING, Any

from .plan import EpisodeSpec

if TYPE_CHECKING:
    from ..scenario.scene import Scene

__all__ = ["MAX_BATCH", "TASKS_PER_WORKER", "balance_order", "make_batches"]

#: Largest automatic batch: bounds the work lost to Ctrl-C and keeps progress moving.
MAX_BATCH = 8
#: Each automatic batch holds at most 1/(TASKS_PER_WORKER × workers) of what remains, so
#: every worker gets several tasks and the last ones are single episodes.
TASKS_PER_WORKER = 4


def make_batches(
    specs: Sequence[EpisodeSpec],
    workers: int,
    batch_size: int | None = None,
    bounds: Sequence[Hashable] | None = None,
) -> list[list[EpisodeSpec]]:
    """Split ``specs`` into consecutive batches, in order.

    Automatic sizes shrink with what remains — ``ceil(remaining / (TASKS_PER_WORKER ×
    workers))``, at most :data:`MAX_BATCH` — down to one episode per task; ``batch_size``
    fixes the size instead. ``bounds`` (one value per spec) keeps apart specs whose
    values differ: no batch holds two (each scene's episodes, each submission's).
    """
    if batch_size is not None and batch_size < 1:
        raise ValueError(f"batch size must be at least 1, got {batch_size}")
    batches: list[list[EpisodeSpec]] = []
    start = 0
    while start < len(specs):
        size = batch_size or min(
            MAX_BATCH, max(1, math.ceil((len(specs) - start) / (TASKS_PER_WORKER * workers)))
        )
        end = min(len(specs), start + size)
        if bounds is not None:
            end = next((i for i in range(start + 1, end) if bounds[i] != bounds[start]), end)
        batches.append(list(specs[start:end]))
        start = end
    return batches


def step_limit(spec: EpisodeSpec, scene: Scene) -> float:
    """The most steps an episode of ``spec`` may take (its parameters, else the scene's)."""
    params = spec.param_dict
    duration = float(params.get("duration", scene.duration))
    dt = float(params.get("dt", scene.dt))
    return duration / dt


def balance_order(specs: Sequence[EpisodeSpec], scene: Scene) -> list[EpisodeSpec]:
    """``specs`` with the longest step limit first, then group by group in turn."""
    group: dict[tuple[str, tuple[tuple[str, Any], ...]], int] = {}
    position: list[tuple[float, int, int, int]] = []
    counts: dict[int, int] = {}
    for index, spec in enumerate(specs):
        g = group.setdefault((spec.controller, spec.params), len(group))
        counts[g] = counts.get(g, 0) + 1
        position.append((-step_limit(spec, scene), counts[g], g, index))
    return [specs[p[3]] for p in sorted(position)]
