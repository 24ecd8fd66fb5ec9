"""Summaries of a sweep: per controller × parameter combination, and a ranking.

Every group reports its success rate with a 95 % Wilson score interval (see
:mod:`puckboard.sweep.stats` for why Wilson), the failures by name, and the mean
progress (laps, mean over the robots of an episode) and collisions (all robots of an
episode) per episode. The ranking pools each controller's episodes over all parameter
values; with the same seeds and parameters for every controller it compares like with
like, which is what grading a class needs.
"""

from __future__ import annotations

import json
from collections import Counter
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from .plan import value_key
from .rows import Outcome
from .stats import PassRate

__all__ = [
    "GroupSummary",
    "controller_labels",
    "format_groups",
    "format_ranking",
    "format_table",
    "params_label",
    "rank_controllers",
    "summarise",
]

#: ``failure`` name for an episode that failed without the judge naming why.
UNNAMED_FAILURE = "unnamed"


@dataclass(frozen=True, kw_only=True)
class GroupSummary(PassRate):
    """The statistics of one controller (with one parameter combination, or pooled)."""

    controller: str
    params: dict[str, Any]
    failures: dict[str, int] = field(default_factory=dict)
    mean_progress_laps: float = 0.0
    mean_collisions: float = 0.0

    @classmethod
    def of(
        cls, controller: str, params: dict[str, Any], outcomes: Sequence[Outcome]
    ) -> GroupSummary:
        n = len(outcomes)
        failures = Counter(o.failure or UNNAMED_FAILURE for o in outcomes if not o.success)
        return cls(
            sum(1 for o in outcomes if o.success),
            n,
            controller=controller,
            params=params,
            failures=dict(sorted(failures.items(), key=lambda kv: (-kv[1], kv[0]))),
            mean_progress_laps=sum(o.progress_laps for o in outcomes) / n if n else 0.0,
            mean_collisions=sum(o.collisions for o in outcomes) / n if n else 0.0,
        )

    # the names the tables and every report's --json give a group's rate and interval
    @property
    def success_rate(self) -> float:
        return self.rate

    @property
    def ci95_low(self) -> float:
        return self.interval[0]

    @property
    def ci95_high(self) -> float:
        return self.interval[1]

    def rate_dict(self) -> dict[str, Any]:
        """The counts, the rate with its interval and the failures, as every report's
        ``--json`` gives a group's pass rate."""
        return {**super().rate_dict(), "failures": dict(self.failures)}

    def to_dict(self) -> dict[str, Any]:
        return {
            "controller": self.controller,
            "params": dict(self.params),
            **self.rate_dict(),
            "mean_progress_laps": self.mean_progress_laps,
            "mean_collisions": self.mean_collisions,
        }


def _dedupe(outcomes: Iterable[Outcome]) -> list[Outcome]:
    # A file resumed by two runs at once may hold an episode twice: count it once.
    by_key: dict[str, Outcome] = {}
    for outcome in outcomes:
        by_key[outcome.key] = outcome
    return list(by_key.values())


def summarise(outcomes: Iterable[Outcome]) -> list[GroupSummary]:
    """One :class:`GroupSummary` per controller × parameter combination, in first-seen order."""
    groups: dict[tuple[str, str], list[Outcome]] = {}
    params_of: dict[tuple[str, str], dict[str, Any]] = {}
    for outcome in _dedupe(outcomes):
        params = dict(outcome.params)
        gkey = (outcome.controller, json.dumps(params, sort_keys=True))
        groups.setdefault(gkey, []).append(outcome)
        params_of[gkey] = params
    return [GroupSummary.of(c, params_of[(c, p)], items) for (c, p), items in groups.items()]


def rank_controllers(outcomes: Iterable[Outcome]) -> list[GroupSummary]:
    """Controllers pooled over all parameter values, best first.

    Order: success rate, then the interval's lower bound (more evidence wins a tie),
    then mean progress, then fewer collisions, then name (so the order is stable).
    """
    pooled: dict[str, list[Outcome]] = {}
    for outcome in _dedupe(outcomes):
        pooled.setdefault(outcome.controller, []).append(outcome)
    ranking = [GroupSummary.of(c, {}, items) for c, items in pooled.items()]
    ranking.sort(
        key=lambda g: (
            -g.success_rate,
            -g.ci95_low,
            -g.mean_progress_laps,
            g.mean_collisions,
            g.controller,
        )
    )
    return ranking


def params_label(
    params: dict[str, Any],
    only: Iterable[str] | None = None,
    written: Mapping[str, Mapping[str, str]] | None = None,
) -> str:
    """``name=value ...``; a value in ``written`` (see :func:`.plan.written_values`) is
    shown as the user wrote it."""
    names = sorted(params) if only is None else [n for n in sorted(params) if n in set(only)]
    texts = written or {}

    def shown(name: str) -> str:
        value = params[name]
        return texts.get(name, {}).get(value_key(value), str(value))

    return " ".join(f"{n}={shown(n)}" for n in names) or "-"


def controller_labels(specs: Iterable[str]) -> dict[str, str]:
    """Short names for tables: ``submissions/alice.py:make_controller`` → ``alice``.

    A file spec is shown by its file name without ``.py`` (plus ``:factory`` unless it is
    the ``--controllers-dir`` convention ``make_controller``), unless that would make two
    controllers look alike; other specs are shown as given.
    """
    from ..behaviours.presets import split_file_spec
    from .discover import FACTORY_NAME

    specs = list(dict.fromkeys(specs))
    short: dict[str, str] = {}
    for spec in specs:
        file_spec = split_file_spec(spec)
        if file_spec is not None:
            path, factory = file_spec
            stem = path.name.removesuffix(".py")
            short[spec] = stem if factory == FACTORY_NAME else f"{stem}:{factory}"
        else:
            short[spec] = spec
    taken = list(short.values())
    return {s: (short[s] if taken.count(short[s]) == 1 else s) for s in specs}


def _failures_label(failures: dict[str, int]) -> str:
    return ", ".join(f"{name} {count}" for name, count in failures.items()) or "-"


def format_table(headers: Sequence[str], rows: Sequence[Sequence[str]], right: set[int]) -> str:
    """A plain-text table: columns as wide as their widest cell, those in ``right``
    right-aligned, a rule under the header."""
    widths = [len(h) for h in headers]
    for row in rows:
        widths = [max(w, len(cell)) for w, cell in zip(widths, row)]

    def line(cells: Sequence[str]) -> str:
        parts = [
            c.rjust(w) if i in right else c.ljust(w) for i, (c, w) in enumerate(zip(cells, widths))
        ]
        return "  ".join(parts).rstrip()

    rule = "  ".join("-" * w for w in widths)
    return "\n".join([line(headers), rule, *(line(r) for r in rows)])


def _stats_cells(g: GroupSummary) -> list[str]:
    return [
        str(g.episodes),
        f"{g.successes}",
        f"{100 * g.success_rate:.0f} %",
        f"[{100 * g.ci95_low:.0f}, {100 * g.ci95_high:.0f}] %",
        f"{g.mean_progress_laps:.2f}",
        f"{g.mean_collisions:.2f}",
        _failures_label(g.failures),
    ]


_STATS_HEADERS = ["n", "ok", "rate", "95% CI (Wilson)", "progress", "collisions", "failures"]


def format_groups(
    groups: Sequence[GroupSummary], written: Mapping[str, Mapping[str, str]] | None = None
) -> str:
    """A plain-text table of groups; only parameters that vary between groups are shown,
    each value as the user wrote it where ``written`` has it (:func:`.plan.written_values`)."""
    varying = {
        name
        for name in {n for g in groups for n in g.params}
        if len({json.dumps(g.params.get(name)) for g in groups}) > 1
    }
    names = controller_labels(g.controller for g in groups)
    rows = [
        [names[g.controller], params_label(g.params, varying, written), *_stats_cells(g)]
        for g in groups
    ]
    headers = ["controller", "parameters", *_STATS_HEADERS]
    return format_table(headers, rows, right=set(range(2, 8)))


def format_ranking(ranking: Sequence[GroupSummary]) -> str:
    """A plain-text ranking table, best controller first."""
    names = controller_labels(g.controller for g in ranking)
    rows = [[str(i), names[g.controller], *_stats_cells(g)] for i, g in enumerate(ranking, 1)]
    headers = ["rank", "controller", *_STATS_HEADERS]
    return format_table(headers, rows, right={0, *range(2, 8)})
