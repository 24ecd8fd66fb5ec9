"""Success rate against a swept parameter, one line per controller, with 95 % intervals.

Error bars are the Wilson score intervals of the summary (asymmetric near 0 and 1, as
they should be). When other parameters are swept too, each of their combinations gets
its own line, labelled with its values, so nothing is silently averaged away.
"""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from typing import Any

from ..viz.figures import new_figure
from .summary import GroupSummary, controller_labels, params_label

__all__ = ["plot_success"]


def plot_success(
    groups: Sequence[GroupSummary],
    parameter: str,
    path: str | os.PathLike[str],
    *,
    title: str | None = None,
) -> None:
    """Write the plot to ``path`` (format from the extension: .png, .svg, .pdf)."""
    if not any(parameter in g.params for g in groups):
        raise ValueError(f"cannot plot against {parameter!r}: it is not a parameter of this sweep")
    lines: dict[tuple[str, str], list[GroupSummary]] = {}
    for group in groups:
        if parameter not in group.params:
            continue
        others = {k: v for k, v in group.params.items() if k != parameter}
        lines.setdefault((group.controller, json.dumps(others, sort_keys=True)), []).append(group)
    varying_others = {
        name
        for _, others_text in lines
        for name in json.loads(others_text)
        if len({json.dumps(json.loads(o).get(name)) for _, o in lines}) > 1
    }
    names = controller_labels(controller for controller, _ in lines)
    fig = new_figure(figsize=(7, 4.5))
    ax = fig.subplots()
    numeric = all(
        isinstance(g.params[parameter], (int, float)) and not isinstance(g.params[parameter], bool)
        for items in lines.values()
        for g in items
    )
    categories: list[Any] = []
    all_x = [g.params[parameter] for items in lines.values() for g in items] if numeric else []
    span = (max(all_x) - min(all_x)) if all_x else 0.0
    # nudge the lines apart sideways so their error bars do not hide each other
    step = (0.012 * span if numeric else 0.06) if len(lines) > 1 else 0.0
    for index, ((controller, others_text), items) in enumerate(lines.items()):
        nudge = (index - (len(lines) - 1) / 2) * step
        if numeric:
            items = sorted(items, key=lambda g: g.params[parameter])
            xs: list[Any] = [g.params[parameter] for g in items]
        else:
            for g in items:
                if str(g.params[parameter]) not in categories:
                    categories.append(str(g.params[parameter]))
            xs = [categories.index(str(g.params[parameter])) for g in items]
        xs = [x + nudge for x in xs]
        ys = [100 * g.success_rate for g in items]
        below = [100 * (g.success_rate - g.ci95_low) for g in items]
        above = [100 * (g.ci95_high - g.success_rate) for g in items]
        label = names[controller]
        extra = params_label(json.loads(others_text), varying_others)
        if extra != "-":
            label = f"{controller} ({extra})"
        ax.errorbar(xs, ys, yerr=[below, above], marker="o", capsize=4, label=label)
    if not numeric:
        ax.set_xticks(range(len(categories)), categories)
    ax.set_xlabel(parameter)
    ax.set_ylabel("success (%, 95 % Wilson CI)")
    ax.set_ylim(-3, 103)
    ax.grid(True, alpha=0.3)
    if title:
        ax.set_title(title)
    ax.legend(fontsize="small")
    fig.tight_layout()
    fig.savefig(path)
