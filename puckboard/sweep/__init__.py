"""Robustness sweeps and grading: many episodes, locally or on a Dask cluster.

One lucky run proves little; a controller is judged by how often it succeeds over seeds,
sensor noise and start poses. This package runs every combination of controller ×
parameter values × seed (:class:`SweepPlan`) in local processes (:class:`LocalExecutor`)
or on a Dask cluster (:class:`DaskExecutor`), writes one row per episode to a resumable
CSV/Parquet file (:func:`open_store`) and summarises success rates with 95 % Wilson
intervals (:func:`wilson_interval`, :class:`SweepResult`).

Nothing is imported here until it is used (Dask, pyarrow, rich and matplotlib not even
then): the command line reads the experiments' defaults (:mod:`.defaults`) while it
builds its parser, and its help stays quick.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .._lazy import lazy_names

_LAZY = {
    "check_plan": ".check",
    "DaskExecutor": ".cluster",
    "FACTORY_NAME": ".discover",
    "controllers_in_dir": ".discover",
    "InlineExecutor": ".executors",
    "LocalExecutor": ".executors",
    "SweepExecutor": ".executors",
    "WorkerLostError": ".executors",
    "RunOptions": ".options",
    "SCENE_CONTROLLERS": ".plan",
    "EpisodeSpec": ".plan",
    "PlanError": ".plan",
    "SweepPlan": ".plan",
    "episode_key": ".plan",
    "make_progress": ".progress",
    "SweepResult": ".run",
    "run_sweep": ".run",
    "wilson_interval": ".stats",
    "open_store": ".store",
    "GroupSummary": ".summary",
    "rank_controllers": ".summary",
    "summarise": ".summary",
}

if TYPE_CHECKING:  # pragma: no cover
    from .check import check_plan
    from .cluster import DaskExecutor
    from .discover import FACTORY_NAME, controllers_in_dir
    from .executors import InlineExecutor, LocalExecutor, SweepExecutor, WorkerLostError
    from .options import RunOptions
    from .plan import SCENE_CONTROLLERS, EpisodeSpec, PlanError, SweepPlan, episode_key
    from .progress import make_progress
    from .run import SweepResult, run_sweep
    from .stats import wilson_interval
    from .store import open_store
    from .summary import GroupSummary, rank_controllers, summarise

__all__ = [
    "FACTORY_NAME",
    "SCENE_CONTROLLERS",
    "DaskExecutor",
    "EpisodeSpec",
    "GroupSummary",
    "InlineExecutor",
    "LocalExecutor",
    "PlanError",
    "RunOptions",
    "SweepExecutor",
    "SweepPlan",
    "SweepResult",
    "WorkerLostError",
    "check_plan",
    "controllers_in_dir",
    "episode_key",
    "make_progress",
    "open_store",
    "rank_controllers",
    "run_sweep",
    "summarise",
    "wilson_interval",
]


__getattr__, __dir__ = lazy_names(__name__, _LAZY, __all__)
