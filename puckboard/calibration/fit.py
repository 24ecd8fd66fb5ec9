"""Each IR sensor's gain and offset, fitted to what it read against the model's response.

Per sensor ``i`` and pose ``k`` the run measured a mean value ``y_k`` (of ``n_k``
readings, sample spread ``s_k``) where the simulator's model (:class:`~.response.WallModel`)
says a sensor of gain 1 and offset 0 reads ``E_k``. The simulator, given a gain ``g`` and
an offset ``o``, has that sensor read ``g·E_k + o`` on average, so the fit is the linear
least squares of ``y_k ≈ g·E_k + o`` (:func:`fit_sensor`).

Which poses count, for sensor ``i``:

* the poses that present it, looking straight at the wall: there its response is at its
  highest and does not change to first order with the robot's heading, which the step
  counters know only to a few degrees (:mod:`.plan`); at a slant its reading would move
  with every heading error;
* the poses where the model says the wall is out of its reach (``E = 0``): the sensor
  reads its offset there, which fixes the offset best;
* neither when the mean has a clipped reading in it (a value at 0 or at full scale is
  not the response: the firmware clamps at 0, the ADC at 4095), nor when the sensor's
  value there lies within three spreads of 0 or of full scale: there the readings that
  happened not to be clipped are the high ones (or the low ones), and a mean of them is
  biased. Which value that is, is decided by the fit, not by the mean read (choosing by
  the mean read would keep the poses whose noise happened to be high and bias the fit
  the same way): a first fit on the poses clear by six spreads, then :data:`REFITS` more,
  each on the poses its predecessor predicts clear by three.

Each pose is weighted by the inverse variance of its mean, ``n_k / s_k²``: the table's
noise grows with the response, so the readings near the wall, a hundred raw units apart
from one reading to the next, weigh less than the quiet ones farther out. The spread is
floored at 1 raw unit (the values are whole numbers). A pose whose readings were all
equal would otherwise weigh without bound.

The residuals are reported as their root mean square in raw units, over the poses used,
with the standard errors of ``g`` and ``o`` (from the weighted fit's covariance, scaled by
its reduced χ², so a model that fits badly reports wide errors, not narrow ones).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..errors import CalibrationError
from ..ir_response import RAW_MAX
from ..records import PROX_NAMES
from .checks import MIN_RESPONSE
from .readings import PoseReading
from .response import WallModel

__all__ = ["MAX_GAIN", "MIN_INFORMATIVE", "SensorFit", "fit_all", "fit_sensor"]

FloatArray = npt.NDArray[np.float64]
BoolArray = npt.NDArray[np.bool_]

#: The weakest response (raw, gain 1) that informs the gain: the model's value about
#: 5.5 cm from a sensor. A fit needs at least :data:`MIN_POINTS` such poses.
MIN_INFORMATIVE = 50.0
MIN_POINTS = 3
#: A gain-1 response at or below this (raw) is the wall out of the sensor's reach.
OUT_OF_REACH = 0.5
#: The largest gain a profile accepts (docs/profiles.md: a gain above 0, at most 10).
MAX_GAIN = 10.0
#: The smallest spread (raw) a pose's readings are taken to have.
SPREAD_FLOOR = 1.0
#: A value within this many spreads of 0 or full scale counts as clipped.
CLIP_SPREADS = 3.0
#: Fits after the first, each choosing its poses by its predecessor's prediction.
REFITS = 2


@dataclass(frozen=True)
class SensorFit:
    """One sensor's fitted gain and offset (raw), their standard errors, the residuals'
    root mean square (raw) over the ``points`` poses used, and where the sensor stops
    detecting a wall straight ahead (m from the sensor; ``None``: never, its offset is
    above the cut-off)."""

    sensor: str
    gain: float
    offset: float
    gain_se: float
    offset_se: float
    rms: float
    points: int
    detection_end: float | None

    def to_dict(self) -> dict[str, object]:
        return {
            "sensor": self.sensor,
            "gain": self.gain,
            "gain_se": self.gain_se,
            "offset": self.offset,
            "offset_se": self.offset_se,
            "residual_rms": self.rms,
            "points": self.points,
            "detection_end_m": self.detection_end,
        }


def fit_sensor(
    expected: npt.ArrayLike, mean: npt.ArrayLike, std: npt.ArrayLike, samples: npt.ArrayLike
) -> tuple[float, float, float, float, float]:
    """Weighted least squares of ``mean ≈ g·expected + o`` (see the module docstring):
    ``(g, o, se_g, se_o, rms)``. Needs two distinct ``expected`` values at least."""
    e = np.asarray(expected, dtype=float)
    y = np.asarray(mean, dtype=float)
    s = np.maximum(np.asarray(std, dtype=float), SPREAD_FLOOR)
    w = np.asarray(samples, dtype=float) / (s * s)
    a = np.column_stack([e, np.ones_like(e)])
    aw = a * w[:, None]
    normal = a.T @ aw
    g, o = np.linalg.solve(normal, aw.T @ y)
    residual = y - (g * e + o)
    dof = max(1, e.size - 2)
    chi2 = float((w * residual * residual).sum()) / dof
    cov = np.linalg.inv(normal) * max(chi2, 1.0)
    return (
        float(g),
        float(o),
        float(math.sqrt(cov[0, 0])),
        float(math.sqrt(cov[1, 1])),
        float(math.sqrt(float((residual * residual).mean()))),
    )


def fit_all(readings: Sequence[PoseReading], model: WallModel) -> list[SensorFit]:
    """Every sensor's fit, in ps0..ps7 order. A sensor that gives no fit (too few usable
    poses, a response too weak, saturated readings) raises one
    :class:`~puckboard.errors.CalibrationError` naming every such sensor and why."""
    expected = np.array([model.expected(r.distance, r.heading) for r in readings]).reshape(-1, 8)
    means = np.array([r.mean for r in readings]).reshape(-1, 8)
    stds = np.array([r.std for r in readings]).reshape(-1, 8)
    low = np.array([r.low for r in readings]).reshape(-1, 8) > 0
    high = np.array([r.high for r in readings]).reshape(-1, 8) > 0
    samples = np.array([r.samples for r in readings], dtype=float)
    presented = np.array([[name in r.sensors for name in PROX_NAMES] for r in readings]).reshape(
        -1, 8
    )
    candidates = ~low & ~high & (presented | (expected <= OUT_OF_REACH))
    spread = np.maximum(stds, SPREAD_FLOOR)
    fits: list[SensorFit] = []
    problems: list[str] = []
    for i, name in enumerate(PROX_NAMES):
        reach = presented[:, i] & (expected[:, i] >= MIN_INFORMATIVE)
        use = _clear_of_the_ends(means[:, i], spread[:, i], 2 * CLIP_SPREADS) & candidates[:, i]
        if int((use & reach).sum()) < MIN_POINTS:
            problems.append(_too_few(name, int((use & reach).sum()), reach, low[:, i], high[:, i]))
            continue
        e, y, s, n = expected[:, i], means[:, i], stds[:, i], samples
        g, o, se_g, se_o, rms = fit_sensor(e[use], y[use], s[use], n[use])
        for _ in range(REFITS):
            # choose the poses again by what the fit predicts there, not by what was read
            use = _clear_of_the_ends(g * e + o, spread[:, i], CLIP_SPREADS) & candidates[:, i]
            if int((use & reach).sum()) < MIN_POINTS:
                break
            g, o, se_g, se_o, rms = fit_sensor(e[use], y[use], s[use], n[use])
        if g < MIN_RESPONSE:
            problems.append(
                f"sensor {name} does not respond: its fitted gain is {g:.3f}, below "
                f"{MIN_RESPONSE:g}"
            )
            continue
        if g > MAX_GAIN:
            problems.append(
                f"sensor {name} answers {g:.1f} times the response table, more than the "
                f"{MAX_GAIN:g} a profile accepts: check the robot's firmware sends calibrated "
                "values"
            )
            continue
        fits.append(
            SensorFit(
                sensor=name,
                gain=g,
                offset=o,
                gain_se=se_g,
                offset_se=se_o,
                rms=rms,
                points=int(use.sum()),
                detection_end=model.detection_end(name, g, o),
            )
        )
    if problems:
        raise CalibrationError("no fit: " + "; ".join(problems))
    return fits


def _clear_of_the_ends(value: FloatArray, spread: FloatArray, spreads: float) -> BoolArray:
    """Where ``value`` lies more than ``spreads`` spreads from 0 and from full scale."""
    margin = spreads * spread
    return np.asarray((value - margin > 0.0) & (value + margin < RAW_MAX))


def _too_few(name: str, usable: int, reach: BoolArray, low: BoolArray, high: BoolArray) -> str:
    at_full, at_zero = int((high & reach).sum()), int((low & reach).sum())
    why = (
        f"{at_full} read full scale ({RAW_MAX:.0f})" if at_full >= at_zero else f"{at_zero} read 0"
    )
    return (
        f"sensor {name}: only {usable} of the {int(reach.sum())} poses that present it to the "
        f"wall give readings clear of 0 and of full scale ({why}); too few to fit"
    )
