"""A scheduling model of a sweep on many workers, fed with measured episode durations.

Scaling a sweep to more cores than the machine at hand has cannot be measured here, but
its arithmetic can be done: a process pool (or Dask) hands the tasks, in order, to
whichever worker is free first — list scheduling — so the time of a sweep on ``W``
workers is

    start-up(W) + makespan(tasks on W workers)

where a task costs the durations of its episodes, plus the cost outside an episode's own
timer (building the controllers and the world) for each, plus the round trip of one task.
:func:`model_sweep` computes that for the batching of earlier versions ("before": plan
order, equal batches of ``min(8, ceil(N / 4W))``) and for today's
(:mod:`puckboard.sweep.batches`: longest first, then group by group; batches that shrink
to single episodes), and the scaling efficiency ``T(1) / (W × T(W))`` of each.

What the model leaves out it cannot show: cores that run slower when all of them are
busy (shared caches, turbo limits, two hardware threads per core), and other programs.
"""

from __future__ import annotations

import heapq
import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from types import SimpleNamespace
from typing import TYPE_CHECKING, Any

from ..sweep.batches import balance_order, make_batches
from ..sweep.plan import EpisodeSpec

if TYPE_CHECKING:
    from ..scenario.scene import Scene

__all__ = ["episodes_from_rows", "makespan", "model_sweep", "old_batches"]


def makespan(task_seconds: Sequence[float], workers: int) -> float:
    """When the last of ``workers`` finishes, given tasks to whichever is free first."""
    free_at = [0.0] * workers
    for seconds in task_seconds:
        heapq.heappush(free_at, heapq.heappop(free_at) + seconds)
    return max(free_at)


def old_batches(specs: Sequence[EpisodeSpec], workers: int) -> list[list[EpisodeSpec]]:
    """The batches of earlier versions: plan order, all of one automatic size."""
    size = min(8, max(1, math.ceil(len(specs) / (4 * workers))))
    return [list(specs[i : i + size]) for i in range(0, len(specs), size)]


def episodes_from_rows(
    rows: Sequence[Mapping[str, Any]],
) -> list[tuple[EpisodeSpec, float]]:
    """(spec, seconds) of each row of a sweep's ``--out`` file, in plan order.

    The plan order is rebuilt as the sweep made it — controller × parameters groups in
    the order they first appear in the file, seeds ascending within each — which is
    exact when every episode has the same step limit (the file lists finished rows).
    """
    groups: dict[tuple[str, str], int] = {}
    found = []
    for row in rows:
        params = json.loads(str(row.get("params") or "{}"))
        spec = EpisodeSpec(str(row["controller"]), int(row["seed"]), tuple(sorted(params.items())))
        group = groups.setdefault(
            (spec.controller, json.dumps(params, sort_keys=True)), len(groups)
        )
        found.append((group, spec.seed, spec, float(row.get("wall_s") or 0.0)))
    return [(spec, seconds) for _, _, spec, seconds in sorted(found, key=lambda f: f[:2])]


def model_sweep(
    episodes: Sequence[tuple[EpisodeSpec, float]],
    *,
    scene: Scene | None = None,
    workers: Sequence[int] = (1, 2, 4, 8, 16),
    startup_s: float | Mapping[int, float] = 0.0,
    startup_after_s: float | Mapping[int, float] | None = None,
    per_episode_s: float = 0.0,
    per_task_s: float = 0.0,
) -> dict[str, Any]:
    """Modelled sweep times and efficiencies, before and after, for each worker count.

    ``episodes`` are (spec, seconds) in plan order; ``scene`` gives the step limits of
    the ordering (any object with ``duration`` and ``dt``; equal limits without one).
    ``startup_s`` is the time the sweep waits for its workers to start, one figure or
    one per worker count; ``startup_after_s`` the same for today's command line, which
    starts them while it prepares the sweep (default: the same as before).
    """
    limits: Any = scene if scene is not None else SimpleNamespace(duration=1.0, dt=1.0)
    cost = {spec: seconds + per_episode_s for spec, seconds in episodes}
    specs = [spec for spec, _ in episodes]
    total = sum(cost.values())

    def start(w: int, after: bool = False) -> float:
        figure = startup_s if startup_after_s is None or not after else startup_after_s
        return figure[w] if isinstance(figure, Mapping) else figure

    def task_seconds(batches: list[list[EpisodeSpec]]) -> list[float]:
        return [sum(cost[s] for s in batch) + per_task_s for batch in batches]

    out: dict[str, Any] = {
        "episodes": len(specs),
        "episode_s": _spread(list(cost.values())),
        "work_s": total,
        "workers": {},
    }
    times: dict[str, dict[int, float]] = {"before": {}, "after": {}}
    for w in sorted({1, *workers}):
        before = task_seconds(old_batches(specs, w))
        after = task_seconds(make_batches(balance_order(specs, limits), w))
        times["before"][w] = start(w) + makespan(before, w)
        times["after"][w] = start(w, after=True) + makespan(after, w)
        out["workers"][w] = {
            "ideal_s": times["before"][1] / w,  # one worker's time, shared without loss
            "tasks_before": len(before),
            "tasks_after": len(after),
            "startup_before_s": start(w),
            "startup_after_s": start(w, after=True),
            "time_before_s": times["before"][w],
            "time_after_s": times["after"][w],
            "efficiency_before": times["before"][1] / (w * times["before"][w]),
            "efficiency_after": times["after"][1] / (w * times["after"][w]),
        }
    out["workers"] = {w: out["workers"][w] for w in workers}
    return out


def _spread(values: list[float]) -> dict[str, float]:
    ordered = sorted(values)
    return {
        "min": ordered[0],
        "median": ordered[len(ordered) // 2],
        "max": ordered[-1],
        "mean": sum(ordered) / len(ordered),
    }


def read_rows(path: str | Path) -> list[dict[str, Any]]:
    """The rows of a sweep's ``--out`` file (CSV or Parquet)."""
    from ..sweep.store import open_store

    if not Path(path).is_file():
        raise ValueError(f"--durations {str(path)!r}: no such file (a sweep's --out file)")
    refused = f"--durations {str(path)!r} is not a sweep's --out file with rows"
    try:
        rows = open_store(path).rows()
    except (ValueError, ImportError, OSError) as exc:
        raise ValueError(f"{refused} ({exc})") from None
    if not rows or not {"controller", "seed", "params", "wall_s"} <= set(rows[0]):
        raise ValueError(refused)
    return rows
