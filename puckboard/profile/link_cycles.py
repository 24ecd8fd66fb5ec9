"""A link cycle by cycle: each cycle's latency from a measured distribution, and readings
that repeat because no new packet came.

A link's :class:`~puckboard.profile.links.LinkTiming` bounds its period and latency; a
real link also varies from one cycle to the next. The University of Fribourg's e-puck2
Wi-Fi benchmark (UNIFR_API_EPUCK, ``examples_benchmark/1_go_on_benchmark/data/``) logged
the wait for each step's sensor packet: half the steps found it there already, most of
the others waited 5-50 ms, and a few waited up to 140 ms. A ground-sensor recording over
the same link (``deinemutterschiff/robotique``, ``Gsensors.csv``) repeats nearly every
value in pairs: the loop ran about twice as fast as fresh data came.

:class:`CycleLatency` is such a distribution as its quantiles (its inverse distribution
function, linear between them: the measured distribution itself, heavy tail included,
not a curve fitted through it); :class:`LinkCycles` is one link's per-cycle model, that
distribution and the share of cycles whose reading repeats the last one, each with its
sources. ``puckboard calibrate link`` measures both for your own link and writes them to
a profile file; the simulator draws each command's latency and decides each cycle's
freshness from them (:mod:`puckboard.sim.link_cycles`).
"""

from __future__ import annotations

import bisect
import itertools
import math
from collections.abc import Mapping
from dataclasses import dataclass

__all__ = ["QUANTILES", "CycleLatency", "LinkCycles"]

#: The quantiles a distribution is written with, by name, and their probabilities.
QUANTILES: dict[str, float] = {
    "min": 0.0,
    "p5": 0.05,
    "p10": 0.10,
    "p25": 0.25,
    "median": 0.50,
    "p75": 0.75,
    "p90": 0.90,
    "p95": 0.95,
    "p99": 0.99,
    "max": 1.0,
}


@dataclass(frozen=True)
class CycleLatency:
    """A distribution of per-cycle latency (s) as (probability, seconds) points.

    The probabilities increase from 0 to 1 and the seconds never fall; a draw is the
    inverse distribution function at a uniform number, linear between the points.
    """

    points: tuple[tuple[float, float], ...]

    def __post_init__(self) -> None:
        probs = [p for p, _ in self.points]
        secs = [s for _, s in self.points]
        if len(self.points) < 2 or probs[0] != 0.0 or probs[-1] != 1.0:
            raise ValueError("a latency distribution needs points from probability 0 to 1")
        if any(b <= a for a, b in itertools.pairwise(probs)):
            raise ValueError("a latency distribution's probabilities must increase")
        if any(not (math.isfinite(s) and s >= 0) for s in secs) or any(
            b < a for a, b in itertools.pairwise(secs)
        ):
            raise ValueError("a latency distribution's seconds must be >= 0 and never fall")

    @classmethod
    def uniform(cls, low: float, high: float) -> CycleLatency:
        """Every latency in ``[low, high]`` equally likely."""
        return cls(((0.0, float(low)), (1.0, float(high))))

    @classmethod
    def of_quantiles(cls, named: Mapping[str, float]) -> CycleLatency:
        """The distribution through the named quantiles given (:data:`QUANTILES`; at
        least two). A missing ``min`` or ``max`` is the nearest one given: the
        distribution never reaches beyond what was measured."""
        points = sorted((QUANTILES[k], float(v)) for k, v in named.items() if k in QUANTILES)
        if len(points) < 2:
            raise ValueError(f"a latency distribution needs at least two of {', '.join(QUANTILES)}")
        if points[0][0] > 0.0:
            points.insert(0, (0.0, points[0][1]))
        if points[-1][0] < 1.0:
            points.append((1.0, points[-1][1]))
        return cls(tuple(points))

    def at(self, u: float) -> float:
        """The latency (s) at probability ``u`` (0..1): the inverse distribution function."""
        probs = [p for p, _ in self.points]
        k = min(max(bisect.bisect_right(probs, u), 1), len(probs) - 1)
        (p0, s0), (p1, s1) = self.points[k - 1], self.points[k]
        return s0 + (s1 - s0) * (min(max(u, p0), p1) - p0) / (p1 - p0)

    def quantile(self, name: str) -> float:
        """The named quantile (``median``, ``p90``, ``max`` ...), in seconds."""
        return self.at(QUANTILES[name])

    def describe(self) -> str:
        """``median 9.3 ms, 90 % 33 ms, max 150 ms``."""
        return (
            f"median {_ms(self.quantile('median'))}, 90 % {_ms(self.quantile('p90'))}, "
            f"max {_ms(self.quantile('max'))}"
        )


def _ms(seconds: float) -> str:
    return f"{seconds * 1e3:.2g} ms" if seconds < 0.01 else f"{seconds * 1e3:.0f} ms"


@dataclass(frozen=True)
class LinkCycles:
    """One link cycle by cycle: ``latency``, each cycle's latency (s) from its sensing to
    its command reaching the wheels; ``repeated``, the (low, high) share of cycles whose
    reading repeats the previous one because no new packet came (one share is drawn per
    run within it); ``sources`` for both, ``assumed`` when some part has none.

    ``fresh_every`` (s), when a measurement knows it, is how often a new packet came: a
    loop whose cycles took ``c`` seconds and repeated a share ``s`` of its readings got
    one every ``c / (1 - s)`` seconds, so a loop of period ``P`` repeats
    ``max(0, 1 - P / fresh_every)`` of them (:meth:`repeated_at`)."""

    latency: CycleLatency
    repeated: tuple[float, float]
    sources: tuple[str, ...]
    assumed: bool
    fresh_every: float | None = None

    def repeated_at(self, period: float) -> float:
        """The share of repeated readings a loop of ``period`` seconds meets: from how
        often packets came when that was measured, else the range's low end."""
        if self.fresh_every is None:
            return self.repeated[0]
        return max(0.0, 1.0 - period / self.fresh_every)

    def __post_init__(self) -> None:
        low, high = self.repeated
        if not 0.0 <= low <= high < 1.0:
            raise ValueError("a share of repeated readings must satisfy 0 <= low <= high < 1")
