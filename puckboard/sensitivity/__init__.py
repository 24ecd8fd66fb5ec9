"""Sensitivity analysis: which of a robot model's uncertain numbers move a controller's
success rate, and by how much.

Each uncertain field of a profile (:func:`puckboard.profile.uncertainty`) is set to
evenly spaced values across its plausible range, one field at a time, on every robot of
the scene; every value runs the same seeds, beside the shipped profile and plausible
robots (``--variation plausible``). :func:`sensitivity_plan` builds the points,
:func:`run_sensitivity` runs them on the sweep machinery (:mod:`puckboard.sweep`: local
cores or Dask, resumable, Ctrl-C keeps what ran) and summarises them
(:class:`SensitivityResult`: rates with 95 % Wilson intervals per field and value, fields
ranked by spread), :func:`format_result` and :func:`plot_sensitivity` show them.

Nothing heavy is imported here: matplotlib loads only when plotting.
"""

from __future__ import annotations

from .plan import DEFAULT_VALUES, Field, Point, SensitivityPlan, field_values, sensitivity_plan
from .plot import plot_sensitivity
from .report import format_result
from .summary import (
    Analysis,
    FieldResult,
    SensitivityResult,
    ValueResult,
    analyse,
    run_sensitivity,
)

__all__ = [
    "DEFAULT_VALUES",
    "Analysis",
    "Field",
    "FieldResult",
    "Point",
    "SensitivityPlan",
    "SensitivityResult",
    "ValueResult",
    "analyse",
    "field_values",
    "format_result",
    "plot_sensitivity",
    "run_sensitivity",
    "sensitivity_plan",
]
