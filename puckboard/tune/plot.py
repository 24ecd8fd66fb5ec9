"""The figure of a study: how the search went, and which parameters mattered.

Left, the optimisation history: each trial's worst-cell rate on the design seeds (a
pruned trial's hollow, at the rounds it ran), and the best so far as a step line. Right,
the parameters' importances by Optuna's own PED-ANOVA evaluator (which parameters set
the best trials apart from the rest; it needs nothing beyond Optuna, where fANOVA needs
scikit-learn), the most important on top. Plain matplotlib,
in the large type of the other figures, rather than Optuna's plotting module, whose
figures are sized for a notebook.
"""

from __future__ import annotations

import os
from typing import Any

from ..viz.figures import COLOURS, FONT, new_figure
from .objective import CellRate, Score
from .run import TuneResult

__all__ = ["plot_tune"]

COLOUR = COLOURS[0]


def _worst(trial: dict[str, Any]) -> float:
    return Score.of([CellRate.from_dict(c) for c in trial["cells"]]).worst


def _history(ax: Any, result: TuneResult) -> None:
    complete = [t for t in result.trials if t["state"] == "complete"]
    pruned = [t for t in result.trials if t["state"] == "pruned"]
    ax.plot(
        [t["number"] for t in complete], [100 * _worst(t) for t in complete], "o",
        color=COLOUR, markersize=9, label="complete",
    )  # fmt: skip
    if pruned:
        ax.plot(
            [t["number"] for t in pruned], [100 * _worst(t) for t in pruned], "o",
            markerfacecolor="none", color=COLOUR, markersize=9, label="pruned (partial)",
        )  # fmt: skip
    best_x, best_y, best = [], [], None
    for trial in sorted(complete, key=lambda t: t["number"]):
        if best is None or trial["value"] > best["value"]:
            best = trial
        best_x.append(trial["number"])
        best_y.append(100 * _worst(best))
    ax.step(best_x, best_y, where="post", color="black", linewidth=2.5, label="best so far")
    ax.set_xlabel("trial", fontsize=FONT)
    ax.set_ylabel("worst cell's success (%)", fontsize=FONT)
    ax.set_ylim(-5, 105)
    ax.set_title("optimisation history", fontsize=FONT)
    ax.legend(fontsize=FONT - 3)


def _importances(ax: Any, result: TuneResult) -> None:
    import optuna

    labels = {p.name: p.label for p in result.spec.params}
    try:
        importances = optuna.importance.get_param_importances(
            result.study, evaluator=optuna.importance.PedAnovaImportanceEvaluator()
        )
    except (ValueError, RuntimeError, ImportError) as exc:  # too few trials, or all equal
        ax.text(0.5, 0.5, f"no importances:\n{exc}", ha="center", va="center", wrap=True)
        ax.set_axis_off()
        return
    names = list(importances)[::-1]
    ax.barh([labels.get(n, n) for n in names], [importances[n] for n in names], color=COLOUR)
    ax.set_xlabel("importance (PED-ANOVA)", fontsize=FONT)
    ax.set_xlim(0, 1)
    ax.set_title("parameter importances", fontsize=FONT)


def plot_tune(result: TuneResult, path: str | os.PathLike[str]) -> None:
    """Write the figure to ``path`` (.png, .svg, .pdf)."""
    fig = new_figure(figsize=(14, 5.5))
    left, right = fig.subplots(1, 2)
    _history(left, result)
    _importances(right, result)
    for ax in (left, right):
        ax.tick_params(labelsize=FONT - 2)
    fig.tight_layout()
    fig.savefig(path)
