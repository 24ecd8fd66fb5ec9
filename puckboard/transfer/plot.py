"""The figure of a transfer report, made to be projected.

Top, the matrix: one row per model (the design band first, then each held-out family),
one column per cell (controller, then scene and profile), each square coloured by its
pass rate and labelled with it and ``k/n``; a pale square was not run. Bottom, one panel
per perturbation: a bar per cell up to its robustness radius on the perturbation's grid
(no bar: already the design model falls below the threshold; hatched: the grid's end cut
the radius short; pale: a point it reached was not run).

Large type, the cells in the same order in every panel, a colour map that reads in grey
and for the common colour blindnesses (cividis).
"""

from __future__ import annotations

import os
from typing import Any

from ..sweep.summary import controller_labels
from ..viz.figures import FONT, OKABE_ITO, new_figure
from .families import DESIGN
from .report import short_name
from .result import Cell, TransferResult

__all__ = ["plot_transfer"]

#: Bar colour of the radius panels.
BAR = OKABE_ITO["blue"]


def _column_labels(result: TransferResult) -> list[str]:
    names = {k: short_name(v) for k, v in controller_labels(result.plan.controllers).items()}
    several_scenes = len(result.plan.scenes) > 1
    labels = []
    for cell in _ordered(result.cells):
        lines = [names[cell.controller]]
        if several_scenes:
            lines.append(cell.scene.replace("two-robot-pass", "pass"))
        lines.append(cell.profile)
        labels.append("\n".join(lines))
    return labels


def _ordered(cells: list[Cell]) -> list[Cell]:
    """Cells grouped by controller (as given), then scene and profile as the plan has them."""
    order = list(dict.fromkeys(c.controller for c in cells))
    return sorted(cells, key=lambda c: order.index(c.controller))


def _matrix(ax: Any, cells: list[Cell], labels: list[str]) -> Any:
    # rows: the design model, then every family any cell has a band of (a family that is
    # the design model itself in one scene has no band there: a blank square)
    rows = {DESIGN: "design (plausible robots)"}
    for cell in cells:
        rows.update({b.family: b.label for b in cell.families if b.family not in rows})
    grid = []
    texts = []
    for family in rows:
        values, words = [], []
        for cell in cells:
            bands = {DESIGN: cell.design, **{b.family: b for b in cell.families}}
            g = bands[family].stats if family in bands else None
            values.append(float("nan") if g is None else 100 * g.success_rate)
            words.append(
                ("not run" if family in bands else "-")
                if g is None
                else f"{100 * g.success_rate:.0f} %\n{g.successes}/{g.episodes}"
            )
        grid.append(values)
        texts.append(words)
    image = ax.imshow(grid, cmap="cividis", vmin=0, vmax=100, aspect="auto")
    for r, words in enumerate(texts):
        for c, word in enumerate(words):
            value = grid[r][c]
            colour = "black" if value == value and value > 60 else "white"
            if value != value:
                colour = "grey"
            ax.text(c, r, word, ha="center", va="center", fontsize=FONT - 2, color=colour,
                    fontweight="bold")  # fmt: skip
    ax.set_yticks(range(len(rows)), list(rows.values()), fontsize=FONT)
    ax.set_xticks(range(len(cells)), labels, fontsize=FONT - 3)
    ax.xaxis.tick_top()
    _separate_controllers(ax, cells)
    ax.set_title("pass rate on each model", fontsize=FONT + 2, fontweight="bold", pad=12)
    return image


def _separate_controllers(ax: Any, cells: list[Cell]) -> None:
    """A line between one controller's columns and the next's."""
    for c in range(1, len(cells)):
        if cells[c].controller != cells[c - 1].controller:
            ax.axvline(c - 0.5, color="black", lw=3)


def _radius_panel(ax: Any, cells: list[Cell], index: int, labels: list[str]) -> None:
    first = cells[0].radii[index]
    grid = [p.scale for p in first.grid]
    positions = {scale: i + 1 for i, scale in enumerate(grid)}  # bar height: grid position
    for c, cell in enumerate(cells):
        r = cell.radii[index].estimate
        if r.radius is None:
            ax.text(c, 0.15, "none", ha="center", va="bottom", fontsize=FONT - 3)
            continue
        ax.bar(c, positions[r.radius], width=0.7, color=BAR,
               alpha=1.0 if r.complete else 0.35, hatch="//" if r.censored else None,
               edgecolor="white" if r.censored else BAR)  # fmt: skip
        ax.text(c, positions[r.radius] + 0.05, ("≥ " if r.censored else "") + first.text(r.radius),
                ha="center", va="bottom", fontsize=FONT - 3)  # fmt: skip
    ax.set_yticks(range(1, len(grid) + 1), list(first.shown), fontsize=FONT - 2)
    ax.set_ylim(0, len(grid) + 0.7)
    ax.set_xlim(-0.5, len(cells) - 0.5)
    ax.set_xticks(range(len(cells)), labels, fontsize=FONT - 3)
    _separate_controllers(ax, cells)
    ax.set_title(f"robustness radius: {first.family} (pass rate stays ≥ "
                 f"{100 * first.estimate.threshold:.0f} %)", fontsize=FONT)  # fmt: skip
    ax.grid(True, axis="y", alpha=0.3)


def plot_transfer(result: TransferResult, path: str | os.PathLike[str]) -> None:
    """Write the figure to ``path`` (.png, .svg, .pdf); needs matplotlib."""
    cells = _ordered(result.cells)
    if not cells:
        raise ValueError("nothing to plot: the report has no cell")
    labels = _column_labels(result)
    n_rows = 1 + len({b.family for c in cells for b in c.families})
    n_radii = len(cells[0].radii)
    width = max(12.0, 4.5 + 1.6 * len(cells))
    heights = [max(3.0, 0.9 * n_rows)] + [2.3] * n_radii
    fig = new_figure(figsize=(width, sum(heights) + 2.5 + 0.6 * n_radii))
    grid = fig.add_gridspec(1 + n_radii, 2, height_ratios=heights, width_ratios=[40, 1])
    image = _matrix(fig.add_subplot(grid[0, 0]), cells, labels)
    bar = fig.colorbar(image, cax=fig.add_subplot(grid[0, 1]))
    bar.set_label("pass rate (%)", fontsize=FONT - 2)
    for i in range(n_radii):
        ax = fig.add_subplot(grid[1 + i, 0])
        _radius_panel(ax, cells, i, labels)
        if i < n_radii - 1:  # the columns are the matrix's: named at its top and at the bottom
            ax.tick_params(axis="x", labelbottom=False)
    seeds = result.to_dict()["seeds"]
    fig.suptitle(
        f"Beyond the design model: seeds {seeds} at every model (95 % Wilson intervals "
        "in the report)",
        fontsize=FONT + 3,
        fontweight="bold",
    )
    fig.tight_layout(rect=(0, 0, 1, 0.96))
    fig.savefig(path, dpi=100, bbox_inches="tight")
