"""The leaderboard's rows: each entry's rates per cell and overall, its verdict, its rank.

An *entry* is a submission's version or a baseline. Its graded episodes give, per graded
cell and pooled, a success rate with its 95 % Wilson interval
(:class:`~puckboard.sweep.summary.GroupSummary`), its median progress and its failures
by name (an episode that ended in error counts under ``error:KIND``, the kinds of
:data:`~puckboard.sweep.rows.ERROR_KINDS`, apart from the judge's own ``timeout``, which
is a run that ended before its goal).

Its *verdict* names what happened to it (:data:`VERDICTS`): ``graded``; a refusal by the
pre-flight check (never ranked); or the kind of error its episodes most often ended in
(still ranked: those episodes count as failures). *Remarks* say what else it did
(printed, wrote files, ticked slower than the control period).

Entries are ranked by the challenge's rule (:data:`~puckboard.challenge.spec.RANKING_KEYS`);
equal keys share a rank; baselines are placed where the rule puts them but take no rank,
so the class's ranks run 1, 2, 3 ...
"""

from __future__ import annotations

import statistics
from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from ..sweep.rows import Outcome
from ..sweep.summary import GroupSummary

__all__ = ["VERDICTS", "Standing", "rank", "verdict_of"]

#: Every verdict an entry can get, and what it means.
VERDICTS: dict[str, str] = {
    "graded": "every graded episode ran",
    "incomplete": "grading was stopped before all its episodes ran: run the same command again",
    "not-python": "the file is not valid Python",
    "import-failed": "importing the file raised an exception",
    "no-factory": "the file defines no controller factory",
    "factory-failed": "the factory raised an exception",
    "wrong-return": "the factory returned something that is not a Controller or a list of layers",
    "layer-raised": "a layer (or the simulation) raised an exception in some episodes",
    "timeout": "it ran past the wall-clock limit (a layer that sleeps, blocks or never returns)",
    "exited": "it ended its process (sys.exit, os._exit)",
    "crashed": "its process was killed or crashed",
    "memory": "it ran out of the memory it may take",
}
#: The verdicts of the pre-flight check that keep an entry from being graded.
REFUSALS = (
    "not-python",
    "import-failed",
    "no-factory",
    "factory-failed",
    "wrong-return",
    "timeout",
    "exited",
    "crashed",
    "memory",
)
#: An error episode's kind → the verdict it gives.
_ERROR_VERDICTS = {
    "exception": "layer-raised",
    "timeout": "timeout",
    "exited": "exited",
    "crashed": "crashed",
    "memory": "memory",
}


@dataclass
class Standing:
    """One entry of the leaderboard; see the module docstring."""

    name: str
    baseline: bool
    planned: int
    version: str | None = None
    file: str | None = None
    first_seen: str | None = None
    graded_at: str | None = None
    verdict: str = "graded"
    verdict_text: str = ""
    remarks: list[str] = field(default_factory=list)
    cells: list[tuple[str, GroupSummary]] = field(default_factory=list)
    overall: GroupSummary | None = None
    median_progress: float = 0.0
    failures: dict[str, int] = field(default_factory=dict)
    rank: int | None = None
    replays: dict[str, str] = field(default_factory=dict)
    details: str = ""

    @property
    def episodes(self) -> int:
        return self.overall.episodes if self.overall is not None else 0

    @property
    def complete(self) -> bool:
        """Checked and every graded episode run: the rule places it."""
        return self.overall is not None and self.episodes >= self.planned

    @property
    def worst_cell(self) -> float:
        return min((s.success_rate for _, s in self.cells), default=0.0)

    def value(self, key: str) -> float:
        """The entry's figure for ranking key ``key``, larger better."""
        overall = self.overall
        if overall is None:
            return float("-inf")
        return {
            "worst_cell_success": self.worst_cell,
            "success": overall.success_rate,
            "success_low": overall.ci95_low,
            "median_progress": self.median_progress,
            "collisions": -overall.mean_collisions,
        }[key]

    def to_dict(self) -> dict[str, Any]:
        overall = self.overall
        return {
            "rank": self.rank,
            "name": self.name,
            "baseline": self.baseline,
            "version": self.version,
            "file": self.file,
            "first_seen": self.first_seen,
            "graded_at": self.graded_at,
            "verdict": self.verdict,
            "verdict_text": self.verdict_text,
            "remarks": list(self.remarks),
            "episodes": self.episodes,
            "planned": self.planned,
            "overall": None if overall is None else overall.rate_dict(),
            "worst_cell_success": self.worst_cell if overall is not None else None,
            "cells": {name: s.rate_dict() for name, s in self.cells},
            "median_progress_laps": self.median_progress,
            "failures": dict(self.failures),
            "replays": dict(self.replays),
        }


def failure_name(outcome: Outcome) -> str:
    """How an unsuccessful episode shows in the failures: the judge's name, or
    ``error:KIND`` for an episode that ended in error."""
    if outcome.failure == "error":
        return f"error:{outcome.error_kind or 'exception'}"
    return outcome.failure or "unnamed"


def summarise_entry(
    standing: Standing, cells: Sequence[str], outcomes: Mapping[str, Sequence[Outcome]]
) -> None:
    """Fill ``standing``'s rates from its outcomes, by graded cell (in ``cells``' order)."""
    everything = [o for cell in cells for o in outcomes.get(cell, ())]
    if not everything:
        return
    standing.cells = [
        (cell, GroupSummary.of(standing.name, {}, list(outcomes.get(cell, ())))) for cell in cells
    ]
    standing.overall = GroupSummary.of(standing.name, {}, everything)
    standing.median_progress = statistics.median(o.progress_laps for o in everything)
    failures = Counter(failure_name(o) for o in everything if not o.success)
    standing.failures = dict(sorted(failures.items(), key=lambda kv: (-kv[1], kv[0])))


def verdict_of(
    standing: Standing, check: Mapping[str, Any] | None, errors: Mapping[str, int], limit: float
) -> tuple[str, str]:
    """``(verdict, words)`` of an entry from its pre-flight ``check`` (``None`` for a
    baseline) and its episodes' error kinds (``errors``, kind → count)."""
    if check is not None and check.get("verdict", "ok") != "ok":
        return str(check["verdict"]), f"not graded: {check.get('message', '')}"
    if errors:
        kind, count = max(errors.items(), key=lambda kv: (kv[1], kv[0]))
        verdict = _ERROR_VERDICTS.get(kind, "layer-raised")
        said = {
            "timeout": f"ran past the {limit:g} s wall-clock limit",
            "exited": "ended its process",
            "crashed": "had its process killed or crash",
            "memory": "ran out of memory",
        }.get(kind, "raised an exception")
        total = sum(errors.values())
        words = f"{count} of {standing.planned} graded episodes {said}"
        if total > count:
            words += f" ({total - count} more ended in other errors)"
        return verdict, words + "; they count as failures"
    if not standing.complete:
        return "incomplete", (
            f"{standing.episodes} of {standing.planned} graded episodes ran: run the same "
            "command again to finish"
        )
    return "graded", ""


def rank(standings: list[Standing], order: Sequence[str]) -> list[Standing]:
    """``standings`` in the rule's order (refused and incomplete ones last, by name),
    with ranks from 1 for the class's entries; equal figures share a rank."""

    def key(s: Standing) -> tuple[float, ...]:
        return tuple(-s.value(k) for k in order)

    placed = [s for s in standings if s.complete]
    rest = [s for s in standings if s not in placed]
    placed.sort(key=lambda s: (key(s), s.baseline, s.name.casefold()))
    rest.sort(key=lambda s: (s.baseline, s.name.casefold()))
    number = 0
    previous: tuple[float, ...] | None = None
    shared = 0
    for standing in placed:
        standing.rank = None
        if standing.baseline:
            continue
        number += 1
        this = key(standing)
        if this == previous:
            standing.rank = shared
        else:
            standing.rank = shared = number
            previous = this
    for standing in rest:
        standing.rank = None
    return placed + rest
