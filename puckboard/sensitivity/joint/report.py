"""The text report of a joint analysis: per controller and profile, the band, what is clear
(or that nothing is), the ranked numbers and the curves of the highest ranked ones.

Sixty numbers' curves do not fit a screen; the text shows the curves of the clear
numbers (at least :data:`SHOWN`), ``--json`` has every curve. Values are shown as people
read them (mm, degrees); ``--json`` has them in SI.
"""

from __future__ import annotations

from ...profile.setting_names import setting_unit
from ...sweep.summary import controller_labels, format_table
from ..units import shown_scale
from .analysis import JointAnalysis, JointResult, Number, verdict
from .estimate import MIN_EVENTS, PASS, PROGRESS, Effect

__all__ = ["SHOWN", "format_joint"]

#: Numbers listed (ranked) and curves shown per analysis when fewer are clear.
SHOWN = 5


def _percent(x: float) -> str:
    return f"{100 * x:.0f} %"


def _value(path: str, value: float) -> str:
    scale, _ = shown_scale(setting_unit(path))
    return f"{value * scale:.4g}"


def _unit(path: str) -> str:
    _, unit = shown_scale(setting_unit(path))
    return f" ({unit})" if unit else ""


def _effect(e: Effect | None) -> str:
    if e is None:
        return "-"
    digits = 2 if e.outcome == PASS else 3
    return f"{e.estimate:+.{digits}f} [{e.low:+.{digits}f}, {e.high:+.{digits}f}]"


def _pairs(count: int) -> str:
    return f"{count} pair" if count == 1 else f"{count} pairs"


def _quarters(n: Number) -> str:
    return " | ".join(_percent(b.rate) for b in n.bins)


def _ranking(a: JointAnalysis) -> str:
    clear = a.clear
    rows = []
    for rank, n in enumerate(a.ranking[: max(SHOWN, len(clear))], 1):
        rows.append(
            [
                str(rank),
                n.name + (" *" if n in clear else ""),
                _effect(n.effect(PASS)),
                _effect(n.effect(PROGRESS)),
                _quarters(n),
            ]
        )
    headers = ["rank", "number", "pass: log-odds low→high", "progress: laps low→high",
               "pass rate by bin"]  # fmt: skip
    return format_table(headers, rows, right=set())


def _curve(n: Number) -> str:
    rows = [
        [
            f"{_value(n.path, b.low)}–{_value(n.path, b.high)}",
            str(b.episodes),
            str(b.successes),
            _percent(b.rate),
            "[{:.0f}, {:.0f}] %".format(*(100 * v for v in b.interval)),
            f"{b.progress:.3f} [{b.progress_low:.3f}, {b.progress_high:.3f}]",
        ]
        for b in n.bins
    ]
    shipped = "" if n.shipped is None else f", shipped {_value(n.path, n.shipped)}"
    title = f"{n.name}{_unit(n.path)}{shipped}"
    return format_table(
        [title, "n", "ok", "rate", "95% CI (Wilson)", "progress (laps, 95% CI)"],
        rows,
        right={1, 2, 3, 4},
    )


def format_analysis(a: JointAnalysis, controller: str) -> str:
    """One controller × profile: band, verdict, ranking, interaction, curves."""
    b = a.band
    failures = ", ".join(f"{k} {v}" for k, v in b.failures.items()) or "-"
    parts = [
        f"{controller} on {a.profile}: plausible robots pass {b.successes} of {b.episodes} "
        f"({_percent(b.success_rate)}, 95 % Wilson {100 * b.ci95_low:.0f}–"
        f"{100 * b.ci95_high:.0f} %); failures: {failures}",
    ]
    if a.ranked_by == PASS:
        parts.append("ranked by pass/fail (logistic regression per number)")
    else:
        parts.append(
            f"ranked by progress (fewer than {MIN_EVENTS} passes or {MIN_EVENTS} failures: too "
            "few for pass/fail to rank anything)"
        )
    parts.append(verdict(a) + " (* its simultaneous 95 % interval leaves out 0)")
    if not a.numbers:
        return "\n".join([*parts, f"{a.profile} has no drawn number that varies."])
    if a.clear:
        parts += ["", _ranking(a)]
    else:
        parts.append("the numbers are not ranked: their order would be noise's")
    pair = a.interaction
    if pair is not None:
        parts.append(
            f"strongest interacting pair, clear: {pair.a} × {pair.b} (product term "
            f"{_effect(pair.effect)}, of {_pairs(pair.pairs_tested)} of the top numbers)"
            if pair.effect.clear
            else f"no interaction is clear at N = {b.episodes} (strongest: {pair.a} × "
            f"{pair.b}, {_effect(pair.effect)}, of {_pairs(pair.pairs_tested)})"
        )
    for n in a.clear:
        parts += ["", _curve(n)]
    return "\n".join(parts)


def format_joint(result: JointResult, *, stored: str | None = None) -> str:
    """The whole report; ``stored`` names the ``--out`` file skipped episodes are in."""
    head = (
        f"{result.scenario}, joint method: plausible robots, every number drawn at once "
        f"(seeds {result.seeds}, {result.bins} equal-count bins per number)"
    )
    sweep = result.sweep
    if sweep is not None:
        speed = f", {sweep.episodes_per_s:.1f} episodes/s" if sweep.ran else ""
        head += f"\n{sweep.episodes_text(stored)}, {sweep.wall_s:.1f} s{speed}"
    names = controller_labels(result.controllers)
    body = [format_analysis(a, names.get(a.controller, a.controller)) for a in result.analyses]
    return "\n\n\n".join([head, *body])
