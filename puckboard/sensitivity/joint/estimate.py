"""The estimators of the joint method, on plain arrays: binned curves, a main-effect index
per number with a simultaneous interval, and the strongest interacting pair.

Every episode is one point in the space of drawn numbers with an outcome, pass/fail and
the robots' progress (laps, a continuous outcome that still orders episodes when nearly
all of them fail). What is estimated, and with what:

* a number's **curve**: the episodes binned by the number into ``bins`` equal-count
  slices of its drawn values (the given-data practice of PAWN and regional sensitivity
  analysis), each bin's pass rate with its 95 % Wilson interval (the same interval as
  every rate of the project) and its mean progress with a 95 % t interval
  (statsmodels);
* its **index**: the slope of a regression of the outcome on the number scaled to its
  drawn range, so that the slope is the change from the lowest to the highest drawn
  value: a logistic regression for pass/fail (the change in log-odds), least squares for
  progress (the change in laps), both statsmodels, each with its interval;
* **clear**: the interval leaves out 0 at a confidence that holds for all the numbers at
  once (Bonferroni: 95 % over the ``m`` numbers tested, so each interval is at
  ``1 − 0.05 / m``). Sixty noise numbers at plain 95 % would mark three by chance;
* the **interaction**: among the :data:`INTERACTION_TOP` highest ranked numbers, each
  pair's product term in the same regression (the rate's change beyond what each number
  does alone), Bonferroni over the pairs tested; the largest is reported, clear or not.

Pass/fail ranks when the episodes hold at least :data:`MIN_EVENTS` passes and as many
failures (the usual events-per-variable floor of a logistic regression); otherwise
progress ranks, and the report says so.
"""

from __future__ import annotations

import itertools
import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from ...sweep.stats import PassRate

__all__ = [
    "ALPHA",
    "DEFAULT_BINS",
    "INTERACTION_TOP",
    "MIN_EVENTS",
    "PASS",
    "PROGRESS",
    "Bin",
    "Effect",
    "Interaction",
    "binned_curve",
    "main_effect",
    "ranking_outcome",
    "strongest_interaction",
]

#: Bins per number unless asked otherwise: quarters, about N/4 episodes each.
DEFAULT_BINS = 4
#: Family-wise error of "clear": 5 % over all the numbers (or pairs) tested together.
ALPHA = 0.05
#: Passes and failures each needed before pass/fail ranks (else progress does).
MIN_EVENTS = 10
#: Numbers whose pairs are searched for an interaction.
INTERACTION_TOP = 5
#: The two outcomes: pass/fail and mean progress of the robots (laps).
PASS, PROGRESS = "pass", "progress"

Array = npt.NDArray[np.float64]


def _statsmodels() -> Any:
    try:
        import statsmodels.api as sm
    except ImportError as exc:
        raise ImportError(
            "the joint sensitivity method needs statsmodels: pip install 'puckboard[analysis]'",
            name=exc.name,
        ) from None
    return sm


@dataclass(frozen=True, kw_only=True)
class Bin(PassRate):
    """The pass rate of the episodes whose number lies in ``[low, high]`` (drawn values,
    SI), and their mean progress with its interval."""

    low: float
    high: float
    progress: float
    progress_low: float
    progress_high: float

    def to_dict(self) -> dict[str, Any]:
        rate_low, rate_high = self.interval
        return {
            "low": self.low, "high": self.high, "episodes": self.episodes,
            "successes": self.successes, "rate": self.rate, "rate_low": rate_low,
            "rate_high": rate_high, "progress": self.progress,
            "progress_low": self.progress_low, "progress_high": self.progress_high,
        }  # fmt: skip


@dataclass(frozen=True)
class Effect:
    """A regression slope from the lowest to the highest drawn value, with its interval
    at ``1 − alpha`` (simultaneous over the numbers tested)."""

    outcome: str
    estimate: float
    low: float
    high: float
    z: float

    @property
    def clear(self) -> bool:
        return self.low > 0.0 or self.high < 0.0

    def to_dict(self) -> dict[str, Any]:
        return {
            "outcome": self.outcome,
            "estimate": self.estimate,
            "ci_low": self.low,
            "ci_high": self.high,
            "z": self.z,
            "clear": self.clear,
        }


@dataclass(frozen=True)
class Interaction:
    """The product term of numbers ``a`` and ``b`` (scaled as in :class:`Effect`)."""

    a: str
    b: str
    effect: Effect
    pairs_tested: int

    def to_dict(self) -> dict[str, Any]:
        return {"a": self.a, "b": self.b, "pairs_tested": self.pairs_tested,
                **self.effect.to_dict()}  # fmt: skip


def _scaled(x: Array) -> Array:
    """``x`` on its drawn range: 0 at the lowest value, 1 at the highest."""
    span = float(np.max(x) - np.min(x))
    return (x - np.min(x)) / span if span > 0 else np.zeros_like(x)


def bin_edges(x: Array, bins: int) -> Array:
    """Equal-count edges of ``x`` (``bins`` + 1 of them, the extremes included)."""
    return np.quantile(x, np.linspace(0.0, 1.0, bins + 1))


def binned_curve(x: Array, success: Array, progress: Array, bins: int) -> list[Bin]:
    """The episodes in ``bins`` equal-count slices of ``x``: rate and progress per bin."""
    sm = _statsmodels()
    edges = bin_edges(x, bins)
    # each episode in exactly one bin: the last edge closes the last bin
    index = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, bins - 1)
    out = []
    for b in range(bins):
        inside = index == b
        n = int(np.sum(inside))
        if n == 0:
            continue
        wins = int(np.sum(success[inside]))
        values = progress[inside]
        if n > 1 and float(np.std(values)) > 0:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # two episodes: a wide interval, said as such
                p_low, p_high = sm.stats.DescrStatsW(values).tconfint_mean(alpha=0.05)
        else:
            p_low = p_high = float(np.mean(values))
        out.append(
            Bin(
                wins,
                n,
                low=float(np.min(x[inside])),
                high=float(np.max(x[inside])),
                progress=float(np.mean(values)),
                progress_low=float(p_low),
                progress_high=float(p_high),
            )
        )
    return out


def ranking_outcome(success: Array) -> str:
    """:data:`PASS` when there are :data:`MIN_EVENTS` passes and failures, else
    :data:`PROGRESS`."""
    wins = int(np.sum(success))
    return PASS if min(wins, len(success) - wins) >= MIN_EVENTS else PROGRESS


def _fit(design: Array, y: Array, outcome: str, alpha: float) -> Effect | None:
    """The last column's coefficient of ``y`` on ``design`` (a constant added), or
    ``None`` when the model cannot be fitted (no variation, complete separation)."""
    sm = _statsmodels()
    exog = sm.add_constant(design, has_constant="add")
    with warnings.catch_warnings():
        # separation, convergence and too-few-episodes warnings: the result is checked below
        warnings.simplefilter("ignore")
        try:
            if outcome == PASS:
                if np.all(y == y[0]):
                    return None
                fitted = sm.GLM(y, exog, family=sm.families.Binomial()).fit()
            else:
                if float(np.std(y)) == 0.0:
                    return None
                fitted = sm.OLS(y, exog).fit()
            estimate = float(fitted.params[-1])
            low, high = (float(v) for v in fitted.conf_int(alpha=alpha)[-1])
            z = float(fitted.tvalues[-1])
        except Exception:  # a model that cannot be fitted (separation, singular) says nothing
            return None
    if not all(math.isfinite(v) for v in (estimate, low, high, z)):
        return None
    return Effect(outcome, estimate, low, high, z)


def main_effect(x: Array, y: Array, outcome: str, tested: int) -> Effect | None:
    """The change in ``outcome`` from the lowest to the highest drawn ``x``, its interval
    simultaneous over ``tested`` numbers; ``None`` when ``x`` or ``y`` does not vary."""
    if float(np.max(x) - np.min(x)) == 0.0:
        return None
    return _fit(_scaled(x)[:, None], y, outcome, ALPHA / max(1, tested))


def strongest_interaction(
    names: Sequence[str], columns: Sequence[Array], y: Array, outcome: str
) -> Interaction | None:
    """The pair of ``columns`` (the highest ranked numbers, best first; at most
    :data:`INTERACTION_TOP` are used) whose product term is largest in size relative to
    its error, its interval simultaneous over the pairs tested; ``None`` with fewer than
    two numbers."""
    top = list(zip(names, columns))[:INTERACTION_TOP]
    pairs = list(itertools.combinations(range(len(top)), 2))
    best: Interaction | None = None
    for i, j in pairs:
        a = _scaled(top[i][1]) - 0.5  # centred: the product is not a copy of either
        b = _scaled(top[j][1]) - 0.5
        effect = _fit(np.column_stack([a, b, a * b]), y, outcome, ALPHA / len(pairs))
        if effect is not None and (best is None or abs(effect.z) > abs(best.effect.z)):
            best = Interaction(top[i][0], top[j][0], effect, len(pairs))
    return best
