"""What a transfer report found, cell by cell: the design band, each family's band and
each perturbation's robustness radius, every rate with its 95 % Wilson interval.

A cell is one controller on one profile in one scene. Its numbers come from the rows of
the sweeps that ran the plan's points (old rows from ``--out`` and new ones alike), so an
interrupted report is summarised from what ran: a point without episodes is shown as not
run, and a radius that reached one is marked incomplete.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from ..sweep import experiment
from ..sweep.plan import params_key, seeds_text
from ..sweep.rows import Outcome
from ..sweep.run import SweepResult
from ..sweep.summary import GroupSummary, summarise
from .families import DESIGN
from .plan import Point, TransferPlan
from .radius import THRESHOLD, GridPoint, Radius, robustness_radius, seeds_for_lower_bound

__all__ = ["Band", "Cell", "RadiusResult", "TransferResult", "analyse", "stats_dict"]


def stats_dict(g: GroupSummary | None) -> dict[str, Any] | None:
    """A band's counts, rate, interval and failures as ``--json`` gives them."""
    if g is None:
        return None
    return {**g.rate_dict(), "mean_progress_laps": g.mean_progress_laps}


@dataclass(frozen=True)
class Band:
    """One model's pass rate in one cell (``stats`` ``None``: not run yet)."""

    family: str
    label: str
    scale: float
    runs_on: str
    stats: GroupSummary | None
    what: str = ""

    def to_dict(self) -> dict[str, Any]:
        return {
            "family": self.family,
            "label": self.label,
            "scale": self.scale,
            "runs_on": self.runs_on,
            "what": self.what,
            "stats": stats_dict(self.stats),
        }


def _point_dict(p: GridPoint | None) -> dict[str, Any] | None:
    if p is None:
        return None
    low, high = p.interval
    return {
        "scale": p.scale,
        "successes": p.successes,
        "episodes": p.episodes,
        "success_rate": p.rate,
        "ci95_low": low,
        "ci95_high": high,
    }


@dataclass(frozen=True)
class RadiusResult:
    """One family's grid in one cell and the radius read off it, both ways
    (:mod:`puckboard.transfer.radius`): ``estimate`` leads, ``lower`` beside it."""

    family: str
    grid: tuple[GridPoint, ...]
    estimate: Radius
    lower: Radius
    #: Each grid scale as people read it (``×2``, ``100 ms``), in the grid's order.
    shown: tuple[str, ...] = ()

    def text(self, scale: float | None) -> str:
        """``scale`` as people read it (one of the grid's)."""
        for point, shown in zip(self.grid, self.shown):
            if point.scale == scale:
                return shown
        return f"×{scale:g}" if scale is not None else "-"

    def to_dict(self) -> dict[str, Any]:
        r = self.estimate
        return {
            "family": self.family,
            "grid": [_point_dict(p) for p in self.grid],
            "shown": list(self.shown),
            "radius": r.radius,
            "by": r.by,
            "threshold": r.threshold,
            "at": _point_dict(r.at),
            "beyond": _point_dict(r.beyond),
            "censored": r.censored,
            "complete": r.complete,
            "radius_lower_bound": self.lower.radius,
            "lower_bound_at": _point_dict(self.lower.at),
        }


@dataclass(frozen=True)
class Cell:
    """One controller on one profile in one scene."""

    scene: str
    controller: str
    profile: str
    design: Band
    families: tuple[Band, ...]
    radii: tuple[RadiusResult, ...]
    not_applicable: tuple[tuple[str, str], ...] = ()

    def to_dict(self) -> dict[str, Any]:
        return {
            "scene": self.scene,
            "controller": self.controller,
            "profile": self.profile,
            "design": stats_dict(self.design.stats),
            "families": [b.to_dict() for b in self.families],
            "radii": [r.to_dict() for r in self.radii],
            "not_applicable": [{"family": f, "why": w} for f, w in self.not_applicable],
        }


def _grid_point(scale: float, g: GroupSummary | None) -> GridPoint:
    if g is None:
        return GridPoint(0, 0, scale=scale)
    return GridPoint(g.successes, g.episodes, scale=scale)


def analyse(
    plan: TransferPlan, outcomes: Mapping[str, Iterable[Outcome]], *, threshold: float = THRESHOLD
) -> list[Cell]:
    """Every cell of ``plan`` from the ``outcomes`` of each scene run on (by scene name);
    outcomes of other parameters are ignored."""
    groups: dict[tuple[str, str, str], GroupSummary] = {}
    for scene, rows in outcomes.items():
        for g in summarise(rows):
            groups[(scene, g.controller, params_key(g.params))] = g

    def stats(controller: str, point: Point) -> GroupSummary | None:
        return groups.get((point.runs_on, controller, plan.point_key(point)))

    cells = []
    for scene in plan.scenes:
        for profile in plan.profiles[scene]:
            points = [p for p in plan.points if p.scene == scene and p.profile == profile]
            for controller in plan.controllers:
                cells.append(_cell(plan, scene, profile, controller, points, stats, threshold))
    return cells


def _cell(
    plan: TransferPlan,
    scene: str,
    profile: str,
    controller: str,
    points: list[Point],
    stats: Callable[[str, Point], GroupSummary | None],
    threshold: float,
) -> Cell:
    design_point = next(p for p in points if p.family == DESIGN)
    design = Band(DESIGN, DESIGN, 1.0, scene, stats(controller, design_point))
    bands, radii = [], []
    dt = (plan.dts or {}).get(scene, 0.0)
    seeds = len(plan.seeds)  # a point with fewer episodes is incomplete
    for family in plan.families:
        mine = [p for p in points if p.family == family.name]
        if not mine:
            continue  # the design model itself here (plan.skipped says why)
        held = next((p for p in mine if p.scale == family.band_scale), None)
        if held is not None:
            label, what = family.label(dt), family.what_at(dt)
            band = stats(controller, held)
            bands.append(Band(family.name, label, held.scale, held.runs_on, band, what))
        if family.has_radius:
            by_scale = {p.scale: p for p in mine}
            grid = tuple(_grid_point(s, stats(controller, by_scale[s])) for s in family.grid)
            radii.append(
                RadiusResult(
                    family.name,
                    grid,
                    robustness_radius(grid, threshold=threshold, by="estimate", episodes=seeds),
                    robustness_radius(grid, threshold=threshold, by="lower", episodes=seeds),
                    tuple(family.scale_text(s, dt) for s in family.grid),
                )
            )
    skipped = tuple(
        (s.family, s.why) for s in plan.skipped if s.scene == scene and s.profile in ("", profile)
    )
    return Cell(scene, controller, profile, design, tuple(bands), tuple(radii), skipped)


@dataclass
class TransferResult:
    """A report as run: the plan, each scene's sweep, and the cells."""

    plan: TransferPlan
    sweeps: list[SweepResult]
    cells: list[Cell] = field(default_factory=list)
    wall_s: float = 0.0
    threshold: float = THRESHOLD
    #: Stopped between two sweeps (a Ctrl-C, or SIGTERM: ``stopped_by_terminate``).
    stopped: bool = False
    stopped_by_terminate: bool = False

    @classmethod
    def of(
        cls, plan: TransferPlan, sweeps: list[SweepResult], wall_s: float = 0.0
    ) -> TransferResult:
        outcomes = {s.plan.scenario: s.outcomes for s in sweeps}
        return cls(plan, sweeps, analyse(plan, outcomes), wall_s)

    @property
    def ran(self) -> int:
        return sum(s.ran for s in self.sweeps)

    @property
    def skipped(self) -> int:
        return sum(s.skipped for s in self.sweeps)

    @property
    def episodes(self) -> int:
        return sum(len(s.outcomes) for s in self.sweeps)

    @property
    def interrupted(self) -> bool:
        return self.stopped or any(s.interrupted for s in self.sweeps)

    @property
    def terminated(self) -> bool:
        return self.stopped_by_terminate or any(s.terminated for s in self.sweeps)

    @property
    def errors(self) -> list[str]:
        return [e for s in self.sweeps for e in s.errors]

    def error_kinds(self) -> dict[str, int]:
        """:meth:`SweepResult.error_kinds <puckboard.sweep.run.SweepResult.error_kinds>`
        of the whole report."""
        total: Counter[str] = Counter()
        for sweep in self.sweeps:
            total.update(sweep.error_kinds())
        return dict(total.most_common())

    @property
    def outcomes(self) -> list[Outcome]:
        """Every outcome of every sweep of the report."""
        return [o for s in self.sweeps for o in s.outcomes]

    # A report counts, times and heads itself as the sweeps it ran do: it is an
    # ExperimentRun (plan, outcomes, ran, skipped, interrupted, errors, wall_s), the
    # sweeps' fields summed.
    @property
    def episodes_per_s(self) -> float:
        """Episodes this run ran per wall-clock second, as a sweep's (0 when none ran)."""
        return experiment.episodes_per_s(self)

    def counts(self) -> dict[str, Any]:
        """:func:`puckboard.sweep.experiment.counts` of the whole report."""
        return experiment.counts(self)

    def episodes_text(self, stored: str | None = None) -> str:
        """:func:`puckboard.sweep.experiment.episodes_text` of the whole report."""
        return experiment.episodes_text(self, stored)

    def to_dict(self) -> dict[str, Any]:
        """The ``--json`` object: the plan, counts, timing and one entry per cell."""
        return {
            "scenes": list(self.plan.scenes),
            "controllers": list(self.plan.controllers),
            "profiles": {k: list(v) for k, v in self.plan.profiles.items()},
            "seeds": seeds_text(self.plan.seeds),
            "fixed": dict(self.plan.fixed or {}),
            "threshold": self.threshold,
            "radius_by": "estimate",
            "seeds_for_lower_bound": seeds_for_lower_bound(self.threshold),
            "families": [f.to_dict() for f in self.plan.families],
            "episodes": self.episodes,
            **self.counts(),
            "episodes_per_s": self.episodes_per_s,
            "cells": [c.to_dict() for c in self.cells],
        }
