"""How an experiment's run went, said the same way by every report that runs sweeps.

A sweep's :class:`~puckboard.sweep.run.SweepResult` and a transfer report (the sweeps it
ran, summed) both answer the same questions: how many episodes were planned, how many ran
now, how many were already in ``--out``, whether it was stopped and by what, which
episodes raised, how long it took. :class:`ExperimentRun` names those fields, so the
counts, the heading line and the rate are written once here and read any run that has
them, and the command line's exit status and timing take either without a cast.
"""

from __future__ import annotations

from collections.abc import Sized
from typing import Any, Protocol

__all__ = ["ExperimentRun", "counts", "episodes_per_s", "episodes_text"]


class ExperimentRun(Protocol):
    """What every experiment's run says of itself (read only)."""

    @property
    def plan(self) -> Sized:
        """The plan: its length is the episodes planned."""

    @property
    def outcomes(self) -> Sized:
        """Every outcome of the plan there is (old and new)."""

    @property
    def ran(self) -> int:
        """Episodes run now."""

    @property
    def skipped(self) -> int:
        """Episodes already in ``--out``, not run again."""

    @property
    def interrupted(self) -> bool:
        """Stopped before the plan was done (Ctrl-C, or SIGTERM)."""

    @property
    def terminated(self) -> bool:
        """Stopped by SIGTERM (``interrupted`` too)."""

    @property
    def errors(self) -> list[str]:
        """The messages of this run's episodes that raised, one per episode."""

    def error_kinds(self) -> dict[str, int]:
        """How those episodes ended (``error_kind`` → count), most first."""

    @property
    def wall_s(self) -> float:
        """Wall-clock seconds it took."""


def counts(run: ExperimentRun) -> dict[str, Any]:
    """How the run went, as every experiment's ``--json`` says it: episodes ``planned``,
    ``ran`` now, ``skipped`` (already in ``--out``), whether it was ``interrupted``, how
    many ``errors`` (episodes that raised), ``wall_s``."""
    return {
        "planned": len(run.plan),
        "ran": run.ran,
        "skipped": run.skipped,
        "interrupted": run.interrupted,
        "errors": len(run.errors),
        "wall_s": run.wall_s,
    }


def episodes_per_s(run: ExperimentRun) -> float:
    """Episodes the run ran per wall-clock second (0 when none ran)."""
    return run.ran / run.wall_s if run.ran and run.wall_s else 0.0


def episodes_text(run: ExperimentRun, stored: str | None = None) -> str:
    """``N of M episodes (R run[, S already in FILE])``: how much of the plan there is
    and where it came from, as every experiment's report heads it; ``stored`` names the
    ``--out`` file (``None``: there is none)."""
    ran = f"{run.ran} run" + (f", {run.skipped} already in {stored}" if stored else "")
    return f"{len(run.outcomes)} of {len(run.plan)} episodes ({ran})"
