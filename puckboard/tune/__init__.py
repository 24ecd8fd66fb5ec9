"""Tuning a controller's numbers for the worst robot, not the average one.

:func:`run_tune` searches the ranges of a controller's parameters (:class:`Param`,
``PATH=LOW:HIGH[:int][:log]``: a factory keyword or a layer's attribute; :class:`Choice`,
``PATH=A,B``, for one that is true/false or a word) with Optuna's
seeded TPE sampler and median pruner, scoring each trial by its worst cell (scene ×
profile) over the design seeds, then the mean, then progress (:class:`Score`). Episodes
run on the sweep machinery (:mod:`puckboard.sweep`: local processes or Dask). The study
lives in a journal file that a Ctrl-C leaves whole and the same command resumes; the
best parameters are run again on validation seeds no trial saw (:class:`TuneResult`,
:func:`format_result`, :func:`plot_tune`).

Nothing heavy is imported here: Optuna and matplotlib load only when a study runs or
is drawn.
"""

from __future__ import annotations

from .objective import Cell, CellRate, Interrupted, Score
from .plot import plot_tune
from .report import format_result, ready_line, result_dict
from .run import TrialEvent, TuneResult, TuneSpec, run_tune
from .space import Choice, Param, SpaceError, check_space, parse_param
from .storage import StudyMismatch

__all__ = [
    "Cell",
    "CellRate",
    "Choice",
    "Interrupted",
    "Param",
    "Score",
    "SpaceError",
    "StudyMismatch",
    "TrialEvent",
    "TuneResult",
    "TuneSpec",
    "check_space",
    "format_result",
    "parse_param",
    "plot_tune",
    "ready_line",
    "result_dict",
    "run_tune",
]
