"""The figure of a sensitivity analysis, made to be read from the back of a lecture hall.

Left, the tornado: one row per field, the field that moves the success rate most at the
top; each controller × profile is a bar from its lowest to its highest rate across the
field's range (pale when the two rates' 95 % intervals overlap), a tick at the shipped
profile's rate, and a dotted line at the rate of plausible robots (``--variation
plausible``). Right, one panel per field in the same order: the rate against the value
with its 95 % Wilson interval, the shipped value as a star and a grey line.

Large type, thick lines, one colour per controller × profile, the same in every panel.
"""

from __future__ import annotations

import math
import os
from typing import Any

from ...sweep.summary import controller_labels
from ...viz.figures import COLOURS, FONT, new_figure
from ..units import shown_scale
from .summary import Analysis, FieldResult, SensitivityResult

__all__ = ["plot_sensitivity"]


def _field_order(analyses: list[Analysis]) -> list[str]:
    """Fields, the one with the largest spread (in any analysis) first."""
    spread: dict[str, float] = {}
    for analysis in analyses:
        for r in analysis.fields:
            spread[r.field.path] = max(spread.get(r.field.path, 0.0), r.spread)
    return sorted(spread, key=lambda p: -spread[p])


def _label(analysis: Analysis, names: dict[str, str]) -> str:
    def rate(g: Any) -> str:
        return "–" if g is None else f"{100 * g.success_rate:.0f} %"

    return (
        f"{names[analysis.controller]} · {analysis.profile}: shipped {rate(analysis.shipped)}, "
        f"plausible {rate(analysis.plausible)}"
    )


def _tornado(ax: Any, analyses: list[Analysis], order: list[str]) -> None:
    rows = len(order)
    width = 0.8 / max(1, len(analyses))
    for index, analysis in enumerate(analyses):
        colour = COLOURS[index % len(COLOURS)]
        by_path = {r.field.path: r for r in analysis.fields}
        for row, path in enumerate(order):
            r = by_path.get(path)
            if r is None or r.lowest is None or r.highest is None:
                continue
            y = rows - 1 - row + 0.4 - (index + 0.5) * width
            low = 100 * r.lowest.stats.success_rate
            high = 100 * r.highest.stats.success_rate
            ax.barh(
                y, max(high - low, 0.6), left=low if high > low else low - 0.3, height=width * 0.9,
                color=colour, alpha=1.0 if r.clear else 0.35, edgecolor=colour,
            )  # fmt: skip
            if analysis.shipped is not None and any(v.shipped for v in r.values):
                shipped = 100 * analysis.shipped.success_rate
                ax.plot([shipped, shipped], [y - width * 0.5, y + width * 0.5], color="black", lw=3)
        if analysis.plausible is not None:
            ax.axvline(100 * analysis.plausible.success_rate, color=colour, ls=":", lw=2.5)
    ax.set_yticks(range(rows), list(reversed(order)), fontsize=FONT)
    ax.set_ylim(-0.6, rows - 0.4)
    ax.set_xlim(-2, 102)
    ax.set_xlabel("success rate across the field's range (%)", fontsize=FONT)
    ax.set_title("which numbers move the rate", fontsize=FONT + 2, fontweight="bold")
    ax.tick_params(axis="x", labelsize=FONT - 2)
    ax.grid(True, axis="x", alpha=0.3)


def _panel(ax: Any, path: str, analyses: list[Analysis]) -> None:
    unit_label = ""
    for index, analysis in enumerate(analyses):
        r: FieldResult | None = next((x for x in analysis.fields if x.field.path == path), None)
        if r is None or not r.values:
            continue
        colour = COLOURS[index % len(COLOURS)]
        scale, unit_label = shown_scale(r.field.unit)
        xs = [v.value * scale for v in r.values]
        ys = [100 * v.stats.success_rate for v in r.values]
        below = [100 * (v.stats.success_rate - v.stats.ci95_low) for v in r.values]
        above = [100 * (v.stats.ci95_high - v.stats.success_rate) for v in r.values]
        ax.errorbar(xs, ys, yerr=[below, above], color=colour, lw=2.5, marker="o", ms=6,
                    capsize=3, elinewidth=1.5)  # fmt: skip
        for v in r.values:
            if v.shipped:
                ax.plot(v.value * scale, 100 * v.stats.success_rate, marker="*", ms=20,
                        color=colour, markeredgecolor="black", zorder=5)  # fmt: skip
        if r.field.shipped_inside:
            ax.axvline(r.field.shipped * scale, color="grey", lw=1.5, ls="--", zorder=0)
    ax.set_title(f"{path} ({unit_label})" if unit_label else path, fontsize=FONT)
    ax.set_ylim(-3, 103)
    ax.tick_params(labelsize=FONT - 3)
    ax.grid(True, alpha=0.3)


def legend_entries(analyses: list[Analysis], names: dict[str, str]) -> tuple[list[Any], list[str]]:
    """The legend's (handles, labels): every mark the figure draws, drawn as it is drawn
    (the plausible rate's dotted line in each analysis's own colour, as in the chart)."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    colours = [COLOURS[i % len(COLOURS)] for i in range(len(analyses))]
    handles: list[Any] = [Line2D([], [], color=c, lw=4) for c in colours]
    labels = [_label(a, names) for a in analyses]
    handles += [
        tuple(Line2D([], [], color=c, ls=":", lw=2.5) for c in colours),
        Line2D([], [], color="black", lw=3),
        tuple(Patch(color=c, alpha=1.0) for c in colours),
        tuple(Patch(color=c, alpha=0.35) for c in colours),
        Line2D([], [], color="black", marker="*", ms=16, lw=0),
        Line2D([], [], color="grey", ls="--", lw=1.5),
    ]
    labels += [
        "dotted line: plausible robots' rate",
        "black tick: the shipped profile's rate",
        "dark bar: lowest and highest rates' 95 % intervals apart (clear)",
        "pale bar: they overlap (not clear)",
        "star: the shipped profile's rate at the shipped value",
        "dashed grey line: the shipped value",
    ]
    return handles, labels


def plot_sensitivity(
    result: SensitivityResult, path: str | os.PathLike[str], *, title: str | None = None
) -> None:
    """Write the figure to ``path`` (.png, .svg, .pdf); needs matplotlib."""
    analyses = result.analyses
    order = _field_order(analyses)
    names = controller_labels(result.plan.sweep.controllers)
    columns = min(4, max(1, math.ceil(math.sqrt(len(order)))))
    panel_rows = max(1, math.ceil(len(order) / columns))
    # at least as wide as the title and the legend need, with few fields too
    fig = new_figure(figsize=(max(15.0, 6.5 + 4.2 * columns), 2.2 + 3.4 * panel_rows))
    grid = fig.add_gridspec(panel_rows, columns + 2, width_ratios=[1.6, 0.25] + [1] * columns)
    _tornado(fig.add_subplot(grid[:, 0]), analyses, order)
    for i, field_path in enumerate(order):
        ax = fig.add_subplot(grid[i // columns, 2 + i % columns])
        _panel(ax, field_path, analyses)
        if i % columns == 0:
            ax.set_ylabel("success (%)", fontsize=FONT - 1)
    handles, labels = legend_entries(analyses, names)
    seeds = result.to_dict()["seeds"]
    heading = title or f"{result.plan.scenario}: success rate, one number at a time"
    fig.suptitle(f"{heading} (seeds {seeds}, 95 % Wilson intervals)",
                 fontsize=FONT + 4, fontweight="bold")  # fmt: skip
    from matplotlib.legend_handler import HandlerTuple

    ncol = min(3 if columns > 2 else 2, len(handles))
    fig.legend(handles, labels, loc="lower center", ncol=ncol, fontsize=FONT - 1,
               frameon=False, handler_map={tuple: HandlerTuple(ndivide=None)})  # fmt: skip
    legend_rows = math.ceil(len(handles) / ncol)
    legend_height = legend_rows * 0.32 / fig.get_figheight() * 1.3
    fig.tight_layout(rect=(0, legend_height + 0.01, 1, 0.95))
    # "tight": whatever the layout, no title, legend or label is cut at the edge
    fig.savefig(path, dpi=100, bbox_inches="tight")
