"""The objective: robust, not average.

A controller that passes every time on one robot model and never on another averages
50 %; on the robot a student holds it fails. So a parameter set is scored by its
**worst cell** (a cell is one scene with one robot profile), ties broken by the mean rate
over the cells and then by the mean progress (laps): :class:`Score` orders exactly so.

Optuna maximises one number, so :attr:`Score.value` folds the three into one float that
orders the same way for scores over the same seeds: the worst rate moves in steps of
``1/n`` (``n`` seeds per cell), the mean rate, scaled below half such a step, in steps of
``1/(n·c)`` (``c`` cells), and the progress, squashed into ``[0, 1)`` and scaled below
half of that, last.

Episodes run on the sweep machinery (:func:`~puckboard.sweep.run_sweep`): one plan per
scene and round of seeds, the profiles as its grid, the trial's values as fixed
parameters. After each round the score so far is reported to Optuna, whose pruner may
stop a trial that is already behind the others at that round.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from ..sweep.rows import Outcome
from ..sweep.stats import PassRate

if TYPE_CHECKING:
    from ..scenario.scene import Scene
    from ..sweep.executors import SweepExecutor
    from ..sweep.progress import Progress

__all__ = ["Cell", "CellRate", "Interrupted", "Score", "cell_rates", "rounds", "run_cells"]


class Interrupted(KeyboardInterrupt):
    """A Ctrl-C (or SIGTERM) that reached a sweep of the study: the sweep kept what
    finished and returned, so it is raised again here to end the study the same way."""

    def __init__(self, terminated: bool = False) -> None:
        super().__init__()
        self.terminated = terminated


@dataclass(frozen=True, order=True)
class Cell:
    """One scene with one robot profile (``profile`` is ``""`` for the scene's own)."""

    scene: str
    profile: str = ""

    @property
    def label(self) -> str:
        return f"{self.scene}, {self.profile}" if self.profile else self.scene


@dataclass(frozen=True, kw_only=True)
class CellRate(PassRate):
    """A cell's pass rate (with its 95 % Wilson interval) and mean progress."""

    cell: Cell
    progress_laps: float = 0.0

    def to_dict(self) -> dict[str, Any]:
        return {
            "scene": self.cell.scene,
            "profile": self.cell.profile or None,
            **self.rate_dict(),
            "mean_progress_laps": self.progress_laps,
        }

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> CellRate:
        return cls(
            int(data["successes"]),
            int(data["episodes"]),
            cell=Cell(str(data["scene"]), str(data.get("profile") or "")),
            progress_laps=float(data.get("mean_progress_laps") or 0.0),
        )


@dataclass(frozen=True, order=True)
class Score:
    """Worst cell's rate, then the mean rate, then the mean progress: compared in that
    order (the dataclass's ordering is the objective's)."""

    worst: float
    mean: float
    progress: float
    #: Episodes per cell, which sets the scale of :attr:`value`; not compared.
    per_cell: int = field(default=1, compare=False)
    cells: int = field(default=1, compare=False)

    @classmethod
    def of(cls, rates: Sequence[CellRate]) -> Score:
        if not rates:
            return cls(0.0, 0.0, 0.0)
        values = [r.rate for r in rates]
        return cls(
            worst=min(values),
            mean=sum(values) / len(values),
            progress=sum(r.progress_laps for r in rates) / len(rates),
            per_cell=max(1, max(r.episodes for r in rates)),
            cells=len(rates),
        )

    @property
    def value(self) -> float:
        """One number ordered as the score is (see the module docstring)."""
        n, c = self.per_cell, self.cells
        squashed = max(0.0, self.progress) / (1.0 + max(0.0, self.progress))  # [0, 1)
        tie = (self.mean + squashed / (2.0 * n * c)) / (2.0 * n)
        return self.worst + tie


def rounds(seeds: range, count: int) -> list[range]:
    """``seeds`` cut into ``count`` consecutive rounds (fewer when there are fewer seeds),
    as even as they go: the pruner compares trials after the same rounds."""
    count = max(1, min(count, len(seeds)))
    cuts = [len(seeds) * i // count for i in range(count + 1)]
    return [seeds[a:b] for a, b in itertools.pairwise(cuts)]


def cell_rates(outcomes: Iterable[tuple[Cell, Outcome]], cells: Sequence[Cell]) -> list[CellRate]:
    """Each cell's rate (in ``cells``' order) from ``(cell, outcome)`` pairs."""
    grouped: dict[Cell, list[Outcome]] = {cell: [] for cell in cells}
    for cell, outcome in outcomes:
        grouped.setdefault(cell, []).append(outcome)
    rates = []
    for cell in cells:
        runs = grouped[cell]
        n = len(runs)
        rates.append(
            CellRate(
                sum(1 for o in runs if o.success),
                n,
                cell=cell,
                progress_laps=sum(o.progress_laps for o in runs) / n if n else 0.0,
            )
        )
    return rates


def run_cells(
    scenes: Sequence[Scene],
    profiles: Sequence[str],
    controller: str,
    seeds: range,
    params: Mapping[str, Any],
    *,
    executor: SweepExecutor | None,
    episode_timeout: float | None = None,
    progress: Progress | None = None,
) -> list[tuple[Cell, Outcome]]:
    """Run ``seeds`` of every cell with ``params`` fixed; the outcomes by cell.

    One sweep plan per scene, with the profiles (when given) as its grid; ``progress``
    counts the episodes of all of them as one. A sweep that was interrupted raises
    :class:`Interrupted` after keeping nothing of its own: the study keeps whole trials,
    not parts.
    """
    found: list[tuple[Cell, Outcome]] = []
    shared = None
    if progress is not None:
        progress.start(len(seeds) * len(scenes) * max(1, len(profiles)))
        shared = _Counted(progress)
    try:
        for scene in scenes:
            found += _run_scene(
                scene, profiles, controller, seeds, params, executor, episode_timeout, shared
            )
    finally:
        if progress is not None:
            progress.close()
    return found


class _Counted:
    """One progress across the scenes' sweeps: each sweep advances it, none restarts it."""

    def __init__(self, progress: Progress) -> None:
        self.progress = progress

    def start(self, total: int, done: int = 0) -> None:
        pass

    def advance(self, n: int) -> None:
        self.progress.advance(n)

    def close(self) -> None:
        pass


def _run_scene(
    scene: Scene,
    profiles: Sequence[str],
    controller: str,
    seeds: range,
    params: Mapping[str, Any],
    executor: SweepExecutor | None,
    episode_timeout: float | None,
    progress: Progress | None,
) -> list[tuple[Cell, Outcome]]:
    from ..sweep.options import RunOptions
    from ..sweep.plan import SweepPlan
    from ..sweep.run import run_sweep

    found: list[tuple[Cell, Outcome]] = []
    plan = SweepPlan(
        scenario=scene.name,
        controllers=(controller,),
        seeds=seeds,
        grid={"robot.profile": tuple(profiles)} if profiles else {},
        fixed=dict(params),
    )
    options = RunOptions(executor=executor, progress=progress, episode_timeout=episode_timeout)
    result = run_sweep(plan, scene, options)
    if result.interrupted:
        raise Interrupted(result.terminated)
    for outcome in result.outcomes:
        profile = str(dict(outcome.params).get("robot.profile", "")) if profiles else ""
        found.append((Cell(scene.name, profile), outcome))
    return found
