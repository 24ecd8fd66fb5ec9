"""The text report of a transfer study: per scene and profile, one table with a column
per controller and a row per model (the design band, each held-out family), then a row
per perturbation's robustness radius.

A band is ``k/n [low, high] %``: successes of episodes and the 95 % Wilson interval. A
radius is the furthest scale of its grid up to which the pass rate stays at or above the
threshold (by point estimate), with the point that supports it and, after a semicolon,
the first scale that fell below; ``≥`` marks a radius the grid's end cut short.
``--json`` holds everything (failures by name, every grid point, the lower-bound radius).
"""

from __future__ import annotations

from ..sweep.plan import seeds_text
from ..sweep.summary import GroupSummary, controller_labels, format_table
from .families import DESIGN
from .radius import GridPoint
from .result import Cell, RadiusResult, TransferResult

__all__ = ["band_text", "format_result", "radius_text"]

DESIGN_WHAT = "the scene with plausible robots (--variation plausible)"


def _interval(low: float, high: float) -> str:
    return f"[{100 * low:.0f}, {100 * high:.0f}] %"


def band_text(g: GroupSummary | None) -> str:
    """``k/n [low, high] %``, or ``not run``."""
    if g is None:
        return "not run"
    return f"{g.successes}/{g.episodes} {_interval(g.ci95_low, g.ci95_high)}"


def _point(p: GridPoint) -> str:
    return f"{p.successes}/{p.episodes}"


def radius_text(r: RadiusResult) -> str:
    """The radius by point estimate, the interval of the point that supports it and the
    first point beyond it."""
    est = r.estimate
    if est.at is None:
        if est.beyond is None:
            return "not run"
        return f"none: {r.text(est.beyond.scale)} {_point(est.beyond)}"
    low, high = est.at.interval
    text = f"{'≥ ' if est.censored else ''}{r.text(est.at.scale)}: {_point(est.at)} "
    text += _interval(low, high)
    if est.beyond is not None:
        text += f"; {r.text(est.beyond.scale)} {_point(est.beyond)}"
    elif not est.complete:
        text += "; further not run"
    return text


def short_name(label: str) -> str:
    """A controller's table label, shorter where it repeats itself
    (``my_controller:my_controller`` → ``my_controller``)."""
    stem, _, factory = label.partition(":")
    return stem if factory == stem else label


def _block(cells: list[Cell], names: dict[str, str]) -> str:
    """One scene and profile: a column per controller (the cells share their models)."""
    first = cells[0]
    rows = [[DESIGN, *(band_text(c.design.stats) for c in cells)]]
    for i, band in enumerate(first.families):
        rows.append([band.label, *(band_text(c.families[i].stats) for c in cells)])
    for i, radius in enumerate(first.radii):
        rows.append([f"radius: {radius.family}", *(radius_text(c.radii[i]) for c in cells)])
    headers = ["model", *(names[c.controller] for c in cells)]
    title = f"{first.scene} · {first.profile}"
    parts = [title, format_table(headers, rows, right=set())]
    for family, why in first.not_applicable:
        parts.append(f"  {family}: not run, {why}")
    return "\n".join(parts)


def _legend(result: TransferResult) -> str:
    """What each model changes, once for the whole report (a radius with its grid)."""
    lines = [f"  {DESIGN}: {DESIGN_WHAT}"]
    seen = {DESIGN}
    for cell in result.cells:
        for band in cell.families:
            if band.label not in seen:
                seen.add(band.label)
                lines.append(f"  {band.label}: {band.what}")
        for radius in cell.radii:
            name = f"radius: {radius.family}"
            if name not in seen:
                seen.add(name)
                what = next(f.what for f in result.plan.families if f.name == radius.family)
                lines.append(f"  {name}: grid {', '.join(radius.shown)}; {what}")
    return "what each model changes:\n" + "\n".join(lines)


def _lower_bound_note(result: TransferResult) -> str:
    needed = result.to_dict()["seeds_for_lower_bound"]
    held = [
        f"{c.scene} · {c.profile} · {c.controller} {r.family} {r.text(r.lower.radius)}"
        for c in result.cells
        for r in c.radii
        if r.lower.radius is not None
    ]
    text = (
        f"radius: the furthest scale up to which the pass rate stays ≥ "
        f"{100 * result.threshold:.0f} % by point estimate (the interval is the supporting "
        f"point's). By the interval's lower bound instead, a point needs at least {needed} "
        "seeds even when every episode passes"
    )
    if held:
        return text + "; by the lower bound: " + ", ".join(held) + "."
    return text + f"; here none holds by the lower bound ({len(result.plan.seeds)} seeds)."


def format_result(result: TransferResult, *, stored: str | None = None) -> str:
    """The whole report; ``stored`` names the ``--out`` file skipped episodes are in."""
    speed = f", {result.episodes_per_s:.1f} episodes/s" if result.ran else ""
    head = (
        f"transfer: {result.episodes_text(stored)}, {result.wall_s:.1f} s{speed}; seeds "
        f"{seeds_text(result.plan.seeds)} at every model"
    )
    names = {k: short_name(v) for k, v in controller_labels(result.plan.controllers).items()}
    blocks: dict[tuple[str, str], list[Cell]] = {}
    for cell in result.cells:
        blocks.setdefault((cell.scene, cell.profile), []).append(cell)
    body = [_block(cells, names) for cells in blocks.values()]
    return "\n\n".join([head, *body, _legend(result), _lower_bound_note(result)])
