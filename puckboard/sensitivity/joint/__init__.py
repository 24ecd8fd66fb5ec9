"""The joint method: plausible robots with every uncertain number drawn at once, one
robot pair per seed; the same episodes give the band (their pass rate), each drawn
number's binned curve and the numbers ranked, or say that nothing is clear at this N.

:func:`joint_plan` builds the plan (one plausible point per controller × profile),
:func:`run_joint` runs it on the sweep machinery and analyses it, :func:`from_rows`
recomputes the analysis from stored rows (``--from``) without running an episode;
:mod:`.estimate` holds the estimators (statsmodels regressions, imported when used),
:func:`format_joint` and :func:`plot_joint` show the result.
"""

from __future__ import annotations

from .analysis import (
    JointAnalysis,
    JointPlan,
    JointResult,
    Number,
    analyse_rows,
    from_rows,
    joint_plan,
    profile_label,
    run_joint,
    verdict,
)
from .estimate import DEFAULT_BINS, MIN_EVENTS, PASS, PROGRESS
from .plot import plot_joint
from .report import format_joint

__all__ = [
    "DEFAULT_BINS",
    "MIN_EVENTS",
    "PASS",
    "PROGRESS",
    "JointAnalysis",
    "JointPlan",
    "JointResult",
    "Number",
    "analyse_rows",
    "format_joint",
    "from_rows",
    "joint_plan",
    "plot_joint",
    "profile_label",
    "run_joint",
    "verdict",
]
