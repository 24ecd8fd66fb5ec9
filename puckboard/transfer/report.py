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

from ..scenario.overrides import link_overrides
from ..scenario.settings import SETTINGS
from ..sweep.plan import seeds_text
from ..sweep.summary import GroupSummary, controller_labels, format_table
from .families import DESIGN
from .plan import measured_link
from .radius import GridPoint
from .result import Cell, RadiusResult, TransferResult

__all__ = ["band_text", "format_result", "radius_text"]

DESIGN_WHAT = "the scene with plausible robots (--variation plausible)"


def _interval(low: float, high: float) -> str:
    return f"[{100 * low:.0f}, {100 * high:.0f}] %"


def band_text(g: GroupSummary | None, seeds: int = 0) -> str:
    """``k/n [low, high] %``, or ``not run``; marked incomplete when fewer than ``seeds``
    episodes ran (an interrupted report)."""
    if g is None:
        return "not run"
    text = f"{g.successes}/{g.episodes} {_interval(g.ci95_low, g.ci95_high)}"
    if g.episodes < seeds:
        text += f" (incomplete: {g.episodes} of {seeds} seeds)"
    return text


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
        text += "; further not run (incomplete)"
    return text


def short_name(label: str) -> str:
    """A controller's table label, shorter where it repeats itself
    (``my_controller:my_controller`` → ``my_controller``)."""
    stem, _, factory = label.partition(":")
    return stem if factory == stem else label


def _block(result: TransferResult, cells: list[Cell], names: dict[str, str]) -> str:
    """One scene and profile: a column per controller (the cells share their models)."""
    first = cells[0]
    seeds = len(result.plan.seeds)
    rows = [[DESIGN, *(band_text(c.design.stats, seeds) for c in cells)]]
    for i, band in enumerate(first.families):
        rows.append([band.label, *(band_text(c.families[i].stats, seeds) for c in cells)])
    for i, radius in enumerate(first.radii):
        rows.append([f"radius: {radius.family}", *(radius_text(c.radii[i]) for c in cells)])
    headers = ["model", *(names[c.controller] for c in cells)]
    title = f"{first.scene} · {first.profile}{_link_note(result, first)}"
    parts = [title, format_table(headers, rows, right=set())]
    for family, why in first.not_applicable:
        parts.append(f"  {family}: not run, {why}")
    return "\n".join(parts)


def _link_note(result: TransferResult, cell: Cell) -> str:
    """`` (its [link]: control every 100 ms, 50 ms latency)`` for a profile that measured
    its link: the design model, and every model that sets no timing, runs at it."""
    design = next(
        (p for p in result.plan.points if p.scene == cell.scene and p.profile == cell.profile),
        None,
    )
    if design is None or not measured_link(design.params):
        return ""
    from ..scenario.scene import Control

    period, latency = (float(design.params[k]) for k in link_overrides((0.0, 0.0)))
    dt = (result.plan.dts or {}).get(cell.scene, 0.0)
    shown = Control.rounded(period, latency, dt) if dt else Control(period, latency)
    return (
        f" (its [link]: control every {shown.period_for(dt) * 1000:g} ms, "
        f"{shown.latency * 1000:g} ms latency)"
    )


def _fixed_text(result: TransferResult, *, settings_only: bool = False) -> str:
    """The ``--set`` values every model shares (``""`` without any); ``settings_only``:
    those that change the model (the scene's settings, not the controller's numbers)."""
    fixed = result.plan.fixed or {}
    return ", ".join(f"{k}={v}" for k, v in fixed.items() if not settings_only or k in SETTINGS)


def _legend(result: TransferResult) -> str:
    """What each model changes, once for the whole report (a radius with its grid), with
    the ``--set`` settings every model shares besides."""
    fixed = _fixed_text(result, settings_only=True)
    also = f"; with {fixed}" if fixed else ""
    lines = [f"  {DESIGN}: {DESIGN_WHAT}{also}"]
    seen = {DESIGN}
    for cell in result.cells:
        for band in cell.families:
            if band.label not in seen:
                seen.add(band.label)
                lines.append(f"  {band.label}: {band.what}{also}")
        for radius in cell.radii:
            name = f"radius: {radius.family}"
            if name not in seen:
                seen.add(name)
                what = next(f.what for f in result.plan.families if f.name == radius.family)
                lines.append(f"  {name}: grid {', '.join(radius.shown)}; {what}{also}")
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
    fixed = _fixed_text(result)
    head = (
        f"transfer: {result.episodes_text(stored)}, {result.wall_s:.1f} s{speed}; seeds "
        f"{seeds_text(result.plan.seeds)} at every model"
        + (f"; every model with {fixed}" if fixed else "")
    )
    if result.interrupted:
        head += (
            "\nINCOMPLETE: the run was stopped; bands and radii marked incomplete ran fewer "
            "than their seeds" + ("; the same command resumes from --out" if stored else "")
        )
    names = {k: short_name(v) for k, v in controller_labels(result.plan.controllers).items()}
    blocks: dict[tuple[str, str], list[Cell]] = {}
    for cell in result.cells:
        blocks.setdefault((cell.scene, cell.profile), []).append(cell)
    body = [_block(result, cells, names) for cells in blocks.values()]
    return "\n\n".join([head, *body, _legend(result), _lower_bound_note(result)])
