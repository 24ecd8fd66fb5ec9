"""The figure of a joint analysis, in the style of the one-at-a-time figure (:mod:`.plot`):
large type, thick lines, one Okabe–Ito colour per controller × profile.

Left, the ranked index chart: one row per number (the highest ranked, at most
:data:`ROWS`), a bar per controller × profile at its index, the effect divided by its
standard error (signed: positive when the ranked outcome rises with the number), dark
when the effect is clear, pale when not. Right, one panel per number in the same order:
the pass rate in each bin with its 95 % Wilson interval, a horizontal bar over the bin's
range of drawn values, the shipped value as a grey dashed line.
"""

from __future__ import annotations

import math
import os
from typing import Any

from ...profile.setting_names import setting_unit
from ...sweep.summary import controller_labels
from ...viz.figures import COLOURS, FONT, new_figure
from ..units import shown_scale
from .analysis import JointAnalysis, JointResult, verdict
from .estimate import PASS, PROGRESS

__all__ = ["ROWS", "joint_figure", "plot_joint"]

#: Numbers drawn: the clear ones and the strongest of the rest, at most this many.
ROWS = 12


def _z(a: JointAnalysis, name: str) -> tuple[float, bool] | None:
    n = next((x for x in a.numbers if x.name == name), None)
    e = None if n is None else n.effect(a.ranked_by)
    return None if e is None else (e.z, e.clear)


def _order(analyses: list[JointAnalysis]) -> list[str]:
    """The clear numbers of every analysis with any, and its three strongest, strongest
    (anywhere) first. An analysis with nothing clear adds none: its order is noise's, and
    the text does not rank it either."""
    strength: dict[str, float] = {}
    for a in analyses:
        for n in [*a.clear, *a.ranking[:3]] if a.clear else []:
            z = _z(a, n.name)
            strength[n.name] = max(strength.get(n.name, 0.0), abs(z[0]) if z else 0.0)
    return sorted(strength, key=lambda k: (-strength[k], k))[:ROWS]


def _chart(ax: Any, analyses: list[JointAnalysis], order: list[str]) -> None:
    width = 0.8 / max(1, len(analyses))
    for index, a in enumerate(analyses):
        colour = COLOURS[index % len(COLOURS)]
        for row, name in enumerate(order):
            z = _z(a, name)
            if z is None:
                continue
            y = len(order) - 1 - row + 0.4 - (index + 0.5) * width
            ax.barh(y, z[0], height=width * 0.9, color=colour, edgecolor=colour,
                    alpha=1.0 if z[1] else 0.3)  # fmt: skip
    ax.axvline(0, color="black", lw=1.5)
    ax.set_yticks(range(len(order)), list(reversed(order)), fontsize=FONT - 1)
    ax.set_ylim(-0.6, len(order) - 0.4)
    ax.set_xlabel("index: effect ÷ its standard error", fontsize=FONT)
    ax.set_title("which numbers move it", fontsize=FONT + 2, fontweight="bold")
    ax.tick_params(axis="x", labelsize=FONT - 2)
    ax.grid(True, axis="x", alpha=0.3)


def _outcome(analyses: list[JointAnalysis]) -> str:
    """What the panels plot: the pass rate, unless every analysis ranks by progress (too
    few passes or failures for a rate to say anything), then progress."""
    return PASS if any(a.ranked_by == PASS for a in analyses) else PROGRESS


def _panel(ax: Any, name: str, analyses: list[JointAnalysis], outcome: str) -> None:
    robot, path = name.split(": ", 1)
    scale, unit = shown_scale(setting_unit(path))
    shipped: list[tuple[float, str]] = []
    for index, a in enumerate(analyses):
        n = next((x for x in a.numbers if x.name == name), None)
        if n is None or not n.bins:
            continue
        colour = COLOURS[index % len(COLOURS)]
        xs = [scale * (b.low + b.high) / 2 for b in n.bins]
        if outcome == PASS:
            ys = [100 * b.rate for b in n.bins]
            below = [100 * (b.rate - b.interval[0]) for b in n.bins]
            above = [100 * (b.interval[1] - b.rate) for b in n.bins]
        else:
            ys = [b.progress for b in n.bins]
            below = [b.progress - b.progress_low for b in n.bins]
            above = [b.progress_high - b.progress for b in n.bins]
        ax.errorbar(
            xs, ys,
            xerr=[[x - scale * b.low for x, b in zip(xs, n.bins)],
                  [scale * b.high - x for x, b in zip(xs, n.bins)]],
            yerr=[below, above],
            color=colour, lw=2.5, marker="o", ms=6, capsize=3, elinewidth=1.5,
        )  # fmt: skip
        if n.shipped is not None:
            shipped.append((n.shipped * scale, colour))
    # each profile's own shipped value: grey where they are one, its colour where not
    one = len({x for x, _ in shipped}) == 1
    for x, colour in shipped[:1] if one else shipped:
        ax.axvline(x, color="grey" if one else colour, lw=1.5, ls="--", zorder=0)
    # robot and number on lines of their own: side by side, long titles run together
    ax.set_title(f"{robot}:\n{path} ({unit})" if unit else f"{robot}:\n{path}", fontsize=FONT - 2)
    if outcome == PASS:
        ax.set_ylim(-3, 103)
    ax.tick_params(labelsize=FONT - 3)
    ax.grid(True, alpha=0.3)


def _label(a: JointAnalysis, names: dict[str, str]) -> str:
    b = a.band
    ranked = "pass/fail" if a.ranked_by == PASS else "progress"
    return (
        f"{names.get(a.controller, a.controller)} · {a.profile}: plausible "
        f"{100 * b.success_rate:.0f} % of {b.episodes}, ranked by {ranked}"
    )


def plot_joint(
    result: JointResult, path: str | os.PathLike[str], *, title: str | None = None
) -> None:
    """Write the figure to ``path`` (.png, .svg, .pdf); needs matplotlib."""
    joint_figure(result, title=title).savefig(path, dpi=100, bbox_inches="tight")


def joint_figure(result: JointResult, *, title: str | None = None) -> Any:
    """The figure (a matplotlib ``Figure``): the chart and panels of the ranked numbers,
    or, where no analysis has a clear number, what the text says instead."""
    analyses = result.analyses
    order = _order(analyses)
    names = controller_labels(result.controllers)
    heading = title or f"{result.scenario}: robots drawn all at once"
    suptitle = (
        f"{heading} (seeds {result.seeds}, one plausible robot pair each; "
        f"{result.bins} bins, 95 % Wilson intervals)"
    )
    if not order:
        return _nothing_ranked(analyses, names, suptitle)
    outcome = _outcome(analyses)
    columns = min(4, max(1, math.ceil(math.sqrt(len(order)))))
    panel_rows = max(1, math.ceil(len(order) / columns))
    fig = new_figure(figsize=(max(15.0, 7.5 + 4.2 * columns), 2.6 + 3.6 * panel_rows))
    from matplotlib.lines import Line2D  # matplotlib is there: new_figure said so

    grid = fig.add_gridspec(panel_rows, columns + 2, width_ratios=[1.7, 0.3] + [1] * columns)
    _chart(fig.add_subplot(grid[:, 0]), analyses, order)
    for i, name in enumerate(order):
        ax = fig.add_subplot(grid[i // columns, 2 + i % columns])
        _panel(ax, name, analyses, outcome)
        if i % columns == 0:
            label = "success (%)" if outcome == PASS else "progress (laps)"
            ax.set_ylabel(label, fontsize=FONT - 1)
    handles = [
        Line2D([], [], color=COLOURS[i % len(COLOURS)], lw=6, label=_label(a, names))
        for i, a in enumerate(analyses)
    ]
    shipped = "shipped value (in its profile's colour where the profiles' differ)"
    handles += [
        Line2D([], [], color="dimgrey", lw=10, label="dark bar: clear (its simultaneous "
                   "95 % interval leaves out 0)"),
        Line2D([], [], color="dimgrey", lw=10, alpha=0.3, label="pale bar: not clear"),
        Line2D([], [], color="grey", ls="--", lw=1.5,
               label=shipped if len(analyses) > 1 else "shipped value"),
        Line2D([], [], color="black", lw=1.5, marker="|", ms=12,
                   label="horizontal bar: the bin's drawn values"),
    ]  # fmt: skip
    fig.suptitle(suptitle, fontsize=FONT + 4, fontweight="bold")
    ncol = 2
    fig.legend(handles=handles, loc="lower center", ncol=ncol, fontsize=FONT - 1,
               frameon=False)  # fmt: skip
    legend_height = math.ceil(len(handles) / ncol) * 0.32 / fig.get_figheight() * 1.3
    fig.tight_layout(rect=(0, legend_height + 0.01, 1, 0.95))
    return fig


def _nothing_ranked(analyses: list[JointAnalysis], names: dict[str, str], suptitle: str) -> Any:
    """No chart and no panels: each analysis's band and verdict, as the text says them."""
    lines = []
    for a in analyses:
        lines += [_label(a, names), f"{verdict(a)}: the numbers are not ranked, their order "
                  "would be noise's", ""]  # fmt: skip
    fig = new_figure(figsize=(15.0, 1.0 + 0.3 * len(lines)))
    fig.suptitle(suptitle, fontsize=FONT + 4, fontweight="bold")
    fig.text(0.02, 0.75, "\n".join(lines).rstrip(), va="top", ha="left", fontsize=FONT)
    return fig
