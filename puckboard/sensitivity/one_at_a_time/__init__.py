"""The one-at-a-time method: each uncertain field of a profile set to evenly spaced
values across its plausible range, one field at a time, on every robot of the scene;
every value runs the same seeds, beside the shipped profile and plausible robots.

:func:`sensitivity_plan` builds the points (:mod:`.plan`), :func:`run_sensitivity` runs
them on the sweep machinery and summarises them (:mod:`.summary`: rates with 95 % Wilson
intervals per field and value, fields ranked by spread), :func:`format_result` and
:func:`plot_sensitivity` show them.
"""

from __future__ import annotations

from .plan import (
    DEFAULT_VALUES,
    FIELD_LABEL,
    PLAUSIBLE,
    SHIPPED,
    VALUE,
    Field,
    Point,
    SensitivityPlan,
    field_values,
    sensitivity_plan,
)
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
    "FIELD_LABEL",
    "PLAUSIBLE",
    "SHIPPED",
    "VALUE",
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
