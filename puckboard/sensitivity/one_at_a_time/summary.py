"""What a sensitivity analysis found: per field and value a success rate with its 95 %
Wilson interval, the fields ranked by how far they move the rate, and the rates of the
shipped robot and of plausible robots.

A field's *spread* is its highest rate minus its lowest across its range (the shipped
point included when the shipped value lies in the range): the length of its bar in a
tornado chart. The highest and lowest of several noisy rates differ even when a field
does nothing, so a spread alone can mislead at a few seeds per value; a field is marked
*clear* when the 95 % intervals of its lowest and its highest rate do not overlap.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from ...scenario.variation import NONE
from ...sweep.options import DEFAULT_RUN, RunOptions
from ...sweep.plan import params_key, seeds_text
from ...sweep.rows import Outcome
from ...sweep.run import SweepResult, run_sweep
from ...sweep.summary import GroupSummary, summarise
from .plan import PLAUSIBLE, SHIPPED, Field, SensitivityPlan

if TYPE_CHECKING:
    from pathlib import Path

    from ...scenario.scene import Scene

__all__ = [
    "Analysis",
    "FieldResult",
    "SensitivityResult",
    "ValueResult",
    "analyse",
    "run_sensitivity",
]


@dataclass(frozen=True)
class ValueResult:
    """One value of a field and the episodes run at it (``shipped``: the shipped point)."""

    value: float
    shipped: bool
    stats: GroupSummary

    def to_dict(self) -> dict[str, Any]:
        return {"value": self.value, "shipped": self.shipped, **self.stats.rate_dict()}


@dataclass(frozen=True)
class FieldResult:
    """One field's curve: its values in increasing order, each with its rate."""

    field: Field
    values: tuple[ValueResult, ...]

    @property
    def lowest(self) -> ValueResult | None:
        return min(self.values, key=lambda v: (v.stats.success_rate, v.value), default=None)

    @property
    def highest(self) -> ValueResult | None:
        return max(self.values, key=lambda v: (v.stats.success_rate, -v.value), default=None)

    @property
    def spread(self) -> float:
        """Highest rate minus lowest rate across the range (0 with fewer than two values)."""
        low, high = self.lowest, self.highest
        if low is None or high is None or len(self.values) < 2:
            return 0.0
        return high.stats.success_rate - low.stats.success_rate

    @property
    def clear(self) -> bool:
        """Whether the lowest and highest rates' 95 % intervals do not overlap."""
        low, high = self.lowest, self.highest
        if low is None or high is None or len(self.values) < 2:
            return False
        return low.stats.ci95_high < high.stats.ci95_low

    def to_dict(self) -> dict[str, Any]:
        f = self.field
        low, high = self.lowest, self.highest
        return {
            "field": f.path,
            "unit": f.unit,
            "low": f.low,
            "high": f.high,
            "shipped_value": f.shipped,
            "kind": f.kind,
            "source": f.source,
            "spread": self.spread,
            "clear": self.clear,
            "lowest_at": None if low is None else low.value,
            "highest_at": None if high is None else high.value,
            "values": [v.to_dict() for v in self.values],
        }


@dataclass(frozen=True)
class Analysis:
    """One controller on one profile: shipped and plausible rates, fields ranked."""

    controller: str
    profile: str
    shipped: GroupSummary | None
    plausible: GroupSummary | None
    fields: tuple[FieldResult, ...]

    def to_dict(self) -> dict[str, Any]:
        return {
            "controller": self.controller,
            "profile": self.profile,
            "shipped": None if self.shipped is None else self.shipped.rate_dict(),
            PLAUSIBLE: None if self.plausible is None else self.plausible.rate_dict(),
            "ranking": [
                {"field": r.field.path, "spread": r.spread, "clear": r.clear} for r in self.fields
            ],
            "fields": [r.to_dict() for r in self.fields],
        }


def analyse(plan: SensitivityPlan, outcomes: Iterable[Outcome]) -> list[Analysis]:
    """Every controller × profile of ``plan``, from the episodes' ``outcomes`` (those of
    the plan's points; others are ignored). A point without episodes (an interrupted run)
    is left out of its curve."""
    groups = {(g.controller, params_key(g.params)): g for g in summarise(outcomes)}
    analyses = []
    for controller in plan.sweep.controllers:
        for profile in plan.profiles:

            def stats(point_key: str, controller: str = controller) -> GroupSummary | None:
                return groups.get((controller, point_key))

            points = [p for p in plan.points if p.profile == profile]
            shipped = next((stats(plan.point_key(p)) for p in points if p.kind == SHIPPED), None)
            plausible = next(
                (stats(plan.point_key(p)) for p in points if p.kind == PLAUSIBLE), None
            )
            results = []
            for f in (f for f in plan.fields if f.profile == profile):
                values = [
                    ValueResult(float(p.value), False, g)
                    for p in points
                    if p.field == f.path and p.value is not None
                    for g in [stats(plan.point_key(p))]
                    if g is not None
                ]
                if shipped is not None and f.shipped_inside and plan.variation == NONE.name:
                    values.append(ValueResult(f.shipped, True, shipped))
                values.sort(key=lambda v: v.value)
                results.append(FieldResult(f, tuple(values)))
            results.sort(key=lambda r: (-r.spread, not r.clear))
            analyses.append(Analysis(controller, profile, shipped, plausible, tuple(results)))
    return analyses


@dataclass
class SensitivityResult:
    """An analysis as run: the plan, the sweep that ran it and what it found."""

    plan: SensitivityPlan
    sweep: SweepResult
    analyses: list[Analysis] = field(default_factory=list)

    @classmethod
    def of(cls, plan: SensitivityPlan, sweep: SweepResult) -> SensitivityResult:
        return cls(plan, sweep, analyse(plan, sweep.outcomes))

    def to_dict(self) -> dict[str, Any]:
        """The ``--json`` object: counts, timing and one entry per controller × profile."""
        return {
            "scenario": self.plan.scenario,
            "controllers": list(self.plan.sweep.controllers),
            "profiles": list(self.plan.profiles),
            "seeds": seeds_text(self.plan.sweep.seeds),
            "values_per_field": self.plan.values,
            "variation": self.plan.variation,
            "fixed": dict(self.plan.sweep.fixed),
            "episodes": len(self.sweep.outcomes),
            **self.sweep.counts(),
            "episodes_per_s": self.sweep.episodes_per_s,
            "analyses": [a.to_dict() for a in self.analyses],
        }


def run_sensitivity(
    plan: SensitivityPlan, scene: Scene | str | Path, options: RunOptions = DEFAULT_RUN
) -> SensitivityResult:
    """Run every episode of ``plan`` not yet in ``options.store`` and summarise all of
    them. The points are a :class:`~puckboard.sweep.SweepPlan`, so
    :func:`~puckboard.sweep.run_sweep` skips what ``--out`` holds and keeps what ran on
    Ctrl-C: an interrupted analysis is summarised from what ran, and the same call
    resumes it."""
    return SensitivityResult.of(plan, run_sweep(plan.sweep, scene, options))
