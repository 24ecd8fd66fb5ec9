"""The leaderboard as files and text: ``results.csv``, the terminal table, the seeds' guard.

``results.csv`` holds one row per entry and view (``final`` once frozen, and
``latest``), in rank order: its rank (empty for a baseline or an entry not ranked), name,
version, when it was first seen and when its grading finished, verdict and remarks, and
its success rate with the 95 % Wilson interval overall, in its worst cell and in each
graded cell, its median progress, its failures and its replays. The page is
:mod:`puckboard.challenge.page`.

Once the seeds are revealed, ``graded-episodes.csv`` adds every graded episode's row
with its seed, so that anyone can run it again (``puckboard run SCENE --seed N ...``).
Before, :func:`seed_free` is the last guard that no page carries one.
"""

from __future__ import annotations

import csv
import io
import json
import re
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from ..recording.atomic import write_atomically
from ..sweep.summary import format_table
from .standings import Standing

if TYPE_CHECKING:
    from .outputs import Outputs
    from .result import Grading

__all__ = ["format_leaderboard", "seed_free", "write_outputs"]


def seed_free(data: Any, seeds: Mapping[str, Sequence[int]]) -> bool:
    """Whether ``data`` (anything JSON can hold) names none of ``seeds`` as a number."""
    text = json.dumps(data)
    return not any(_mentions(text, seed) for cell in seeds.values() for seed in cell)


def _mentions(text: str, number: int) -> bool:
    return re.search(rf"(?<![\d.]){number}(?![\d])", text) is not None


def _percent(rate: float) -> str:
    return f"{100 * rate:.0f} %"


def _failures(failures: Mapping[str, int]) -> str:
    return ", ".join(f"{name} {count}" for name, count in failures.items()) or "-"


def _rows(grading: Grading) -> list[tuple[str, Standing]]:
    views = [(grading.view, s) for s in grading.standings]
    if grading.latest is not None:
        views += [("latest", s) for s in grading.latest]
    return views


def results_csv(grading: Grading) -> str:
    """The text of ``results.csv`` (see the module docstring)."""
    cells = [c.name for c in grading.challenge.graded]
    header = [
        "view", "rank", "name", "baseline", "version", "file", "first_seen", "graded_at",
        "verdict", "verdict_text", "remarks", "episodes", "planned", "successes",
        "success_rate", "ci95_low", "ci95_high", "worst_cell_success",
    ]  # fmt: skip
    for cell in cells:
        header += [f"cell.{cell}.success_rate", f"cell.{cell}.ci95_low", f"cell.{cell}.ci95_high"]
    header += ["median_progress_laps", "failures", "replay_worst", "replay_success"]
    text = io.StringIO(newline="")
    writer = csv.writer(text)
    writer.writerow(header)
    for view, s in _rows(grading):
        overall = s.overall
        row: list[Any] = [
            view, s.rank or "", s.name, s.baseline, s.version or "", s.file or "",
            s.first_seen or "", s.graded_at or "", s.verdict, s.verdict_text,
            "; ".join(s.remarks), s.episodes, s.planned,
        ]  # fmt: skip
        if overall is None:
            row += ["", "", "", "", ""]
        else:
            row += [overall.successes, overall.success_rate, overall.ci95_low, overall.ci95_high]
            row += [s.worst_cell]
        by_cell = dict(s.cells)
        for cell in cells:
            summary = by_cell.get(cell)
            row += (
                ["", "", ""]
                if summary is None
                else [summary.success_rate, summary.ci95_low, summary.ci95_high]
            )
        row += [s.median_progress if overall is not None else "", _failures(s.failures)]
        row += [s.replays.get("worst", ""), s.replays.get("success", "")]
        writer.writerow(row)
    return text.getvalue()


def format_leaderboard(grading: Grading, standings: Sequence[Standing] | None = None) -> str:
    """The terminal table of a view (default: the one the leaderboard leads with)."""
    cells = [c.name for c in grading.challenge.graded]
    rows = []
    for s in grading.standings if standings is None else standings:
        overall = s.overall
        name = f"{s.name} (baseline)" if s.baseline else s.name
        if overall is None:
            figures = ["-"] * (3 + len(cells))
        else:
            by_cell = dict(s.cells)
            figures = [
                f"{_percent(overall.success_rate)} [{100 * overall.ci95_low:.0f}, "
                f"{100 * overall.ci95_high:.0f}]",
                _percent(s.worst_cell),
                *(f"{by_cell[c].successes}/{by_cell[c].episodes}" for c in cells),
                f"{s.median_progress:.2f}",
            ]
        rows.append([str(s.rank or "-"), name, *figures, s.verdict])
    headers = ["rank", "entry", "success [95% CI]", "worst cell", *cells, "progress", "verdict"]
    return format_table(headers, rows, right={0, *range(2, 4 + len(cells))})


def write_outputs(
    grading: Grading,
    outputs: Outputs,
    rows: Sequence[Mapping[str, Any]],
    seeds: Mapping[str, Sequence[int]],
) -> None:
    """``results.csv``, ``leaderboard.html`` and, once revealed, ``graded-episodes.csv``
    (``rows``: every graded episode's, with its seed; ``seeds``: every graded cell's)."""
    from .page import leaderboard_html

    page = leaderboard_html(grading)
    csv_text = results_csv(grading)
    if grading.seeds is None and not (seed_free(page, seeds) and seed_free(csv_text, seeds)):
        raise RuntimeError("the leaderboard would name a graded seed before --reveal; not written")
    write_atomically(outputs.results, csv_text.encode("utf-8"))
    write_atomically(outputs.leaderboard, page.encode("utf-8"))
    if grading.seeds is not None:
        write_atomically(
            outputs.folder / "graded-episodes.csv", _episodes_csv(rows).encode("utf-8")
        )


def _episodes_csv(rows: Sequence[Mapping[str, Any]]) -> str:
    columns: list[str] = []
    for row in rows:
        columns += [c for c in row if c not in columns]
    text = io.StringIO(newline="")
    writer = csv.DictWriter(text, fieldnames=columns, restval="")
    writer.writeheader()
    writer.writerows(rows)
    return text.getvalue()
