"""The text report of a sensitivity analysis: per controller and profile, the shipped and
plausible rates, the fields ranked by how far they move the rate, then each field's
curve value by value.

Values are shown as people read them (mm, degrees); ``--json`` has them in SI.
"""

from __future__ import annotations

from ...sweep.summary import GroupSummary, controller_labels, format_table
from ..units import describe_value, shown_scale, value_digits
from .summary import Analysis, FieldResult, SensitivityResult

__all__ = ["format_analysis", "format_result"]


def _percent(x: float) -> str:
    return f"{100 * x:.0f} %"


def _interval(g: GroupSummary) -> str:
    return f"[{100 * g.ci95_low:.0f}, {100 * g.ci95_high:.0f}] %"


def _failures(g: GroupSummary) -> str:
    return ", ".join(f"{name} {count}" for name, count in g.failures.items()) or "-"


def _range(r: FieldResult) -> str:
    f = r.field
    scale, unit = shown_scale(f.unit)
    suffix = unit if unit in ("", "°") else f" {unit}"
    return f"{f.low * scale:.4g}–{f.high * scale:.4g}{suffix}"


def _digits(r: FieldResult) -> int:
    scale, _ = shown_scale(r.field.unit)
    return value_digits([v.value * scale for v in r.values])


def _at(r: FieldResult, which: str) -> str:
    point = r.lowest if which == "low" else r.highest
    if point is None:
        return "-"
    shown = describe_value(point.value, r.field.unit, _digits(r))
    return f"{_percent(point.stats.success_rate)} at {shown}"


def _overall(label: str, g: GroupSummary | None) -> list[str]:
    if g is None:
        return [label, "not run", "", "", ""]
    return [
        label,
        f"{g.successes} of {g.episodes}",
        _percent(g.success_rate),
        _interval(g),
        _failures(g),
    ]


def _ranking(analysis: Analysis) -> str:
    rows = []
    for rank, r in enumerate(analysis.fields, 1):
        rows.append(
            [
                str(rank) if r.spread > 0 else "-",  # no spread: nothing to rank it by
                r.field.path,
                _range(r),
                _percent(r.spread) + (" *" if r.clear else "  "),
                _at(r, "low"),
                _at(r, "high"),
            ]
        )
    headers = ["rank", "field", "range", "spread", "lowest rate", "highest rate"]
    return format_table(headers, rows, right={0, 3})


def _curve(r: FieldResult) -> str:
    f = r.field
    scale, unit = shown_scale(f.unit)
    digits = _digits(r)
    rows = [
        [
            f"{v.value * scale:.{digits}g}" + (" (shipped)" if v.shipped else ""),
            str(v.stats.episodes),
            str(v.stats.successes),
            _percent(v.stats.success_rate),
            _interval(v.stats),
            _failures(v.stats),
        ]
        for v in r.values
    ]
    title = f"{f.path} ({unit})" if unit else f.path
    table = format_table(
        [title, "n", "ok", "rate", "95% CI (Wilson)", "failures"], rows, right={1, 2, 3, 4}
    )
    return f"{table}\n  range: {f.kind}: {f.source}"


def format_analysis(analysis: Analysis, controller: str, seeds: str) -> str:
    """One controller × profile: its rates, the ranking and every field's curve."""
    overall = format_table(
        ["", "success", "rate", "95% CI (Wilson)", "failures"],
        [
            _overall("shipped profile", analysis.shipped),
            _overall("--variation plausible", analysis.plausible),
        ],
        right={1, 2, 3},
    )
    parts = [f"{controller} on {analysis.profile} (seeds {seeds})", "", overall]
    flat = any(r.spread == 0 for r in analysis.fields)
    if analysis.fields:
        parts += [
            "",
            "fields ranked by how far they move the success rate across their range "
            "(* the lowest and highest rates' 95 % intervals do not overlap"
            + ("; - no spread: the same rate at every value, nothing to rank" if flat else "")
            + "):",
            _ranking(analysis),
        ]
        for r in analysis.fields:
            parts += ["", _curve(r)]
    else:
        parts += ["", f"{analysis.profile} has no uncertain field to vary here."]
    return "\n".join(parts)


def format_result(result: SensitivityResult, *, stored: str | None = None) -> str:
    """The whole report; ``stored`` names the ``--out`` file the skipped episodes are in."""
    sweep = result.sweep
    speed = f", {sweep.episodes_per_s:.1f} episodes/s" if sweep.ran else ""
    seeds = result.to_dict()["seeds"]
    head = f"{result.plan.scenario}: {sweep.episodes_text(stored)}, {sweep.wall_s:.1f} s{speed}"
    names = controller_labels(result.plan.sweep.controllers)
    body = [format_analysis(a, names[a.controller], seeds) for a in result.analyses]
    return "\n\n\n".join([head, *body])
