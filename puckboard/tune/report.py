"""What a study reports: the best parameters, their rates per cell on the design and on
the validation seeds, a warning when validation falls below design, and the line that
runs the tuned controller.

The validation rates are the ones to quote: the best of many trials on the same seeds is
biased upwards (it was chosen for doing well on them), the validation seeds were never
seen. When a cell's validation interval lies wholly below its design interval the
tuning fitted the seeds rather than the robots (:meth:`TuneResult.overfit`), and the
report says so.
"""

from __future__ import annotations

import shlex
from typing import Any

from .objective import CellRate, Score
from .run import TuneResult, seeds_text

__all__ = ["format_result", "ready_line", "result_dict"]


def ready_line(result: TuneResult) -> str:
    """``--controller SPEC --set NAME=V ...``: the best parameters for ``run`` or
    ``sweep``, in the order the study's ``--param`` gave them, each word quoted for a
    POSIX shell where it needs it (a path with a space or a non-ASCII letter pastes)."""
    if result.best is None:
        return ""
    values = result.best["params"]
    parts = ["--controller", result.spec.controller]
    for p in result.spec.params:
        parts += ["--set", f"{p.name}={_value(values[p.name])}"]
    return shlex.join(parts)


def _value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"  # as --set reads it back
    return f"{value:.6g}" if isinstance(value, float) else str(value)


def _rate(rate: CellRate) -> str:
    low, high = rate.interval
    return (
        f"{100 * rate.rate:5.1f} % ({100 * low:.0f}–{100 * high:.0f} %, "
        f"{rate.successes}/{rate.episodes})"
    )


def format_result(result: TuneResult, *, stored: str | None = None) -> str:
    """The report as text (see the module docstring)."""
    spec = result.spec
    alongside = (
        f", {result.alongside} by another command on it meanwhile" if result.alongside else ""
    )
    lines = [
        f"{len(result.trials)} trials ({result.ran} run now, {result.skipped} from "
        f"{stored or 'the study'}{alongside}; {result.pruned} pruned), {result.wall_s:.1f} s"
    ]
    ran, spared = result.episodes()
    if spared:
        lines.append(f"pruning spared {spared} of {ran + spared} design episodes")
    if result.best is None:
        lines.append("no trial completed: nothing to report yet")
        return "\n".join(lines)
    score = Score.of(result.design)
    lines += ["", f"best: trial {result.best['number']}"]
    width = max(len(p.label) for p in spec.params)
    for p in spec.params:
        lines.append(f"  {p.label:<{width}} = {_value(result.best['params'][p.name])}")
    cell_width = max(len(r.cell.label) for r in result.design)
    lines += [
        "",
        f"{'cell':<{cell_width}}  design (seeds {seeds_text(spec.seeds)})"
        f"{'':14}validation (seeds {seeds_text(spec.validate)})",
    ]
    validation = {r.cell: r for r in result.validation}
    for rate in result.design:
        other = validation.get(rate.cell)
        shown = _rate(other) if other is not None else "not run"
        lines.append(f"{rate.cell.label:<{cell_width}}  {_rate(rate):<34}{shown}")
    lines.append(
        f"worst cell {100 * score.worst:.1f} %, mean {100 * score.mean:.1f} %, "
        f"progress {score.progress:.2f} laps (design)"
    )
    for cell in result.overfit():
        lines.append(
            f"warning: {cell.label}: validation is below design beyond both intervals; the "
            "tuning fitted the design seeds: use more of them"
        )
    lines += ["", "use it:", f"  {ready_line(result)}"]
    return "\n".join(lines)


def result_dict(result: TuneResult) -> dict[str, Any]:
    """The ``--json`` object: the study's command, every trial, the best parameters and
    their rates per cell, the over-fitting warning and the ready-to-use line."""
    ran, spared = result.episodes()
    best = None
    if result.best is not None:
        best = {
            "trial": result.best["number"],
            "params": {p.label: result.best["params"][p.name] for p in result.spec.params},
            "score": result.best["value"],
        }
    return {
        **result.spec.command(),
        "validate": seeds_text(result.spec.validate),
        "trials": result.trials,
        "ran": result.ran,
        "skipped": result.skipped,
        "run_alongside": result.alongside,
        "pruned": result.pruned,
        "design_episodes": ran,
        "episodes_spared_by_pruning": spared,
        "wall_s": result.wall_s,
        "best": best,
        "design": [r.to_dict() for r in result.design],
        "validation": [r.to_dict() for r in result.validation],
        "overfit": [c.label for c in result.overfit()],
        "use": ready_line(result),
    }
