"""The robustness radius: how far a perturbation may grow before the pass rate drops.

A continuous perturbation (the noise levels, a link's timing, a surface's numbers) is
run at the scales of a grid declared before anything runs, ordered outward from the
design model (scale 1). The radius is the furthest scale up to which the pass rate
*stays* at or above :data:`THRESHOLD` (95 %): walking outward, the first scale that falls
below ends it, whatever the scales beyond it give. That keeps a lucky far point from
claiming ground a nearer failure has lost.

"At or above 95 %" can be read two ways, and both are reported:

* ``estimate``: the observed rate (k of n) is at least 95 %. At 20 seeds that is 19 or
  20 of 20. This is the radius reports lead with, always beside the 95 % Wilson interval
  of the point that supports it, so a reader sees how little 20 seeds pin down.
* ``lower``: the interval's lower bound is at least 95 %, a claim about the true rate.
  Even n of n reaches that only from :func:`seeds_for_lower_bound` seeds (73 at 95 %):
  at the default seed counts it is ``None`` for every controller, which says something
  about the number of seeds, not about the controllers. It is the radius to quote once a
  study runs that many.

Everything here is a pure function of counts: no episode, no plan.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from ..sweep.stats import Z95, PassRate, wilson_interval

__all__ = [
    "BY",
    "THRESHOLD",
    "GridPoint",
    "Radius",
    "robustness_radius",
    "seeds_for_lower_bound",
]

#: The pass rate a perturbation must keep (the issue's ≥ 95 %).
THRESHOLD = 0.95
#: How a point is judged to keep the rate: its point estimate, or its Wilson lower bound.
BY = ("estimate", "lower")


@dataclass(frozen=True, kw_only=True)
class GridPoint(PassRate):
    """The pass rate at one scale of a grid (``episodes`` 0: not run yet)."""

    scale: float

    def keeps(self, threshold: float, by: str) -> bool:
        """Whether this point's rate is at least ``threshold``, judged ``by``."""
        if self.episodes == 0:
            return False
        if by == "estimate":
            return self.successes >= threshold * self.episodes - 1e-9  # 19 of 20 is 95 %
        return self.interval[0] >= threshold


@dataclass(frozen=True)
class Radius:
    """The radius read off one grid.

    ``radius`` is the furthest scale that keeps the rate (``None``: already the first,
    the design model, falls below). ``at`` is the point that supports it, ``beyond`` the
    first point that fell below (``None`` when none did: the radius is at least the
    grid's end, ``censored``). ``complete`` is false when a point the walk reached had no
    episodes (an interrupted run): the radius is then only as far as what ran.
    """

    radius: float | None
    at: GridPoint | None
    beyond: GridPoint | None
    complete: bool
    by: str
    threshold: float

    @property
    def censored(self) -> bool:
        """Whether every scale of the grid kept the rate: the true radius may be larger."""
        return self.complete and self.beyond is None and self.radius is not None


def robustness_radius(
    points: Sequence[GridPoint],
    *,
    threshold: float = THRESHOLD,
    by: str = "estimate",
    episodes: int = 1,
) -> Radius:
    """The radius of ``points`` (a grid in its declared order, outward from the design
    model): the last scale before the first that falls below ``threshold``. A point with
    fewer than ``episodes`` episodes (an interrupted run) ends the walk, incomplete."""
    if by not in BY:
        raise ValueError(f"by must be one of {', '.join(BY)}, got {by!r}")
    if not 0.0 < threshold <= 1.0:
        raise ValueError(f"threshold must be in (0, 1], got {threshold}")
    at: GridPoint | None = None
    for point in points:
        if point.episodes < max(1, episodes):
            return Radius(None if at is None else at.scale, at, None, False, by, threshold)
        if not point.keeps(threshold, by):
            return Radius(None if at is None else at.scale, at, point, True, by, threshold)
        at = point
    return Radius(None if at is None else at.scale, at, None, at is not None, by, threshold)


def seeds_for_lower_bound(threshold: float = THRESHOLD, z: float = Z95) -> int:
    """The fewest episodes at which n of n has a Wilson lower bound of at least
    ``threshold``: n / (n + z²) ≥ t, so n ≥ t·z² / (1 − t)."""
    if not 0.0 < threshold < 1.0:
        raise ValueError(f"threshold must be in (0, 1), got {threshold}")
    n = math.ceil(threshold * z * z / (1.0 - threshold) - 1e-9)
    while wilson_interval(n, n)[0] < threshold:  # guard the rounding at the boundary
        n += 1
    return n
