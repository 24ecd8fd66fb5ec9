"""Transfer: a controller judged on models it was not designed on.

A controller is designed on its scene with plausible robots. :mod:`.families` lists the
held-out models (each as data: settings, scaled settings, a variation, a replacement
scene, a scale grid), :func:`transfer_plan` turns scenes × profiles × families into
points on the sweep machinery, :func:`run_transfer_plan` runs them (local cores or
Dask, resumable, Ctrl-C keeps what ran; :func:`run_transfer` is the whole report from the
names ``puckboard transfer`` takes), :class:`TransferResult` holds each cell's bands with
95 % Wilson intervals and each perturbation's robustness radius
(:func:`robustness_radius`), and :func:`format_result` and :func:`plot_transfer` show
them. Nothing heavy is imported here: matplotlib loads only when plotting.
"""

from __future__ import annotations

from .families import DESIGN, FAMILIES, Family, choose_families
from .plan import DEFAULT_SEEDS, Point, TransferPlan, plan_from_names, transfer_plan
from .plot import plot_transfer
from .radius import THRESHOLD, GridPoint, Radius, robustness_radius, seeds_for_lower_bound
from .report import format_result
from .result import Cell, TransferResult
from .run import run_transfer, run_transfer_plan

__all__ = [
    "DEFAULT_SEEDS",
    "DESIGN",
    "FAMILIES",
    "THRESHOLD",
    "Cell",
    "Family",
    "GridPoint",
    "Point",
    "Radius",
    "TransferPlan",
    "TransferResult",
    "choose_families",
    "format_result",
    "plan_from_names",
    "plot_transfer",
    "robustness_radius",
    "run_transfer",
    "run_transfer_plan",
    "seeds_for_lower_bound",
    "transfer_plan",
]
