"""Sensitivity analysis: which of a robot model's uncertain numbers move a controller's
success rate, and by how much. Two methods, each in its own package, both on the sweep
machinery (:mod:`puckboard.sweep`: local cores or Dask, resumable, Ctrl-C keeps what ran):

* :mod:`.one_at_a_time`: each uncertain field of a profile
  (:func:`puckboard.profile.uncertainty`) set to evenly spaced values across its
  plausible range, one field at a time, beside the shipped profile and plausible robots
  (:func:`sensitivity_plan`, :func:`run_sensitivity`, :func:`format_result`,
  :func:`plot_sensitivity`);
* :mod:`.joint`: plausible robots with every number drawn at once; the same episodes
  give the band, each number's binned curve and a ranking (:func:`joint_plan`,
  :func:`run_joint`, :func:`from_rows`, :func:`format_joint`, :func:`plot_joint`).

The joint method's rows are those of the one-at-a-time method's plausible point, so
either method's ``--out`` file feeds the other. Values are shown as people read them
(:mod:`.units`). Nothing heavy is imported here: matplotlib loads only when plotting,
statsmodels only when the joint method ranks.
"""

from __future__ import annotations

from .joint import (
    JointAnalysis,
    JointPlan,
    JointResult,
    analyse_rows,
    format_joint,
    from_rows,
    joint_plan,
    plot_joint,
    run_joint,
)
from .one_at_a_time import (
    DEFAULT_VALUES,
    Analysis,
    Field,
    FieldResult,
    Point,
    SensitivityPlan,
    SensitivityResult,
    ValueResult,
    analyse,
    field_values,
    format_result,
    plot_sensitivity,
    run_sensitivity,
    sensitivity_plan,
)

__all__ = [
    "DEFAULT_VALUES",
    "Analysis",
    "Field",
    "FieldResult",
    "JointAnalysis",
    "JointPlan",
    "JointResult",
    "Point",
    "SensitivityPlan",
    "SensitivityResult",
    "ValueResult",
    "analyse",
    "analyse_rows",
    "field_values",
    "format_joint",
    "format_result",
    "from_rows",
    "joint_plan",
    "plot_joint",
    "plot_sensitivity",
    "run_joint",
    "run_sensitivity",
    "sensitivity_plan",
]
