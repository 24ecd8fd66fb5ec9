"""Confidence intervals for success rates.

A sweep estimates a controller's success probability *p* from *k* successes in *n*
episodes. We report the **Wilson score interval** (Wilson 1927) at 95 %:

.. math::

    \\frac{\\hat p + \\frac{z^2}{2n}}{1 + \\frac{z^2}{n}} \\pm
    \\frac{z}{1 + \\frac{z^2}{n}} \\sqrt{\\frac{\\hat p (1 - \\hat p)}{n} + \\frac{z^2}{4 n^2}}

Why Wilson and not the textbook Wald interval p̂ ± z·sqrt(p̂(1−p̂)/n): sweeps are small
(tens of seeds) and good controllers succeed almost always, exactly where Wald fails — at
10/10 it gives the absurd interval [1, 1], and its coverage is far below 95 % for small n
or p near 0 or 1. Wilson inverts the score test, so it stays inside [0, 1], is never zero
width, and keeps close to nominal coverage at small n (Brown, Cai & DasGupta, *Interval
Estimation for a Binomial Proportion*, Statistical Science 2001, recommend it for
n < 40). Clopper–Pearson ("exact") is the other common choice but is conservative —
wider than needed — and needs the beta quantile function (SciPy); Wilson needs only a
square root.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

__all__ = ["Z95", "PassRate", "wilson_interval"]

#: Two-sided 95 % standard normal quantile, Φ⁻¹(0.975).
Z95 = 1.959963984540054


def wilson_interval(successes: int, trials: int, z: float = Z95) -> tuple[float, float]:
    """The Wilson score interval ``(low, high)`` for ``successes`` out of ``trials``.

    With no trials nothing is known, so the interval is the whole ``(0.0, 1.0)``.
    """
    if trials < 0 or successes < 0 or successes > trials:
        raise ValueError(f"need 0 <= successes <= trials, got {successes}/{trials}")
    if trials == 0:
        return 0.0, 1.0
    n = float(trials)
    p = successes / n
    z2 = z * z
    denominator = 1.0 + z2 / n
    centre = (p + z2 / (2.0 * n)) / denominator
    half = (z / denominator) * math.sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n))
    # Exact at the ends: at 0/n the lower bound is 0, at n/n the upper bound is 1.
    low = 0.0 if successes == 0 else max(0.0, centre - half)
    high = 1.0 if successes == trials else min(1.0, centre + half)
    return low, high


@dataclass(frozen=True)
class PassRate:
    """``successes`` of ``episodes`` passed: the rate and its 95 % Wilson interval.

    The one pass rate every report holds, a sweep's group, a transfer grid's point and
    a study's cell alike (each a subclass adding what it is the rate of), so the rate,
    the interval and their ``--json`` names are written once.
    """

    successes: int
    episodes: int

    @property
    def rate(self) -> float:
        """``successes / episodes`` (0 when there are none)."""
        return self.successes / self.episodes if self.episodes else 0.0

    @property
    def interval(self) -> tuple[float, float]:
        """The 95 % Wilson interval of the rate (``(0, 1)`` when there are no episodes)."""
        return wilson_interval(self.successes, self.episodes)

    def rate_dict(self) -> dict[str, Any]:
        """The counts and the rate with its interval, as every report's ``--json`` gives
        a pass rate."""
        low, high = self.interval
        return {
            "episodes": self.episodes,
            "successes": self.successes,
            "success_rate": self.rate,
            "ci95_low": low,
            "ci95_high": high,
        }
