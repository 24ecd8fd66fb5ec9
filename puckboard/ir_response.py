"""The IR proximity sensor's response curve: distance (m) → raw e-puck value.

The curve is the lookup table of Webots' ``E-puckDistanceSensor.proto``, which Cyberbotics
describe as the result of calibrations on a real e-puck. Webots interpolates it linearly
and, beyond its last entry (7 cm), keeps the last value (≈67): a real sensor never reads
exactly zero, because ambient reflections always return a little light. That baseline
is why the classic e-puck tutorials test ``value > 80`` for "something is there".

The table's third column is the real sensor's noise, a standard deviation expressed as a
fraction of the response; :func:`relative_sigma` interpolates it the same way.

What an e-puck sends is not this raw value but a *calibrated* one: at start-up (and on
request) the firmware measures each sensor with nothing in front of it and subtracts that
baseline from every later reading, clamping at 0. So the curve a robot's software
inverts is ``C(d) = T(d) − T(∞)`` (:data:`CALIBRATED`): 0 m → 4028, 5 mm → 2066,
1 cm → 1399, 1.5 cm → 534, 2 cm → 317, 3 cm → 168, 4 cm → 91, 5 cm → 53, 7 cm and
beyond → 0. :func:`distance_from_calibrated` is the one conversion from such values to a
distance, used alike by the real robot's adapter, the emulated robot and the simulator,
so a robot converts the same values to the same distances wherever it runs.
:func:`calibrated_from_distance` is its inverse inside the range.

Enki's analytic curve (``m(c − x0²)/(x² − 2·x0·x + c)``) agrees with this table within
about 30 % from 3 to 7 cm but is 60 % higher at 0.5 cm; the table is used because it is
measured, not fitted.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

if TYPE_CHECKING:
    from .profile import RobotProfile

__all__ = [
    "CALIBRATED",
    "FAR_RAW",
    "RAW_MAX",
    "TABLE",
    "TABLE_RANGE",
    "calibrated_from_distance",
    "cutoff_value",
    "distance_from_calibrated",
    "distances_from_calibrated",
    "raw_from_distance",
    "relative_sigma",
]

#: (distance m, raw value, noise σ as a fraction of the value), Webots e-puck table.
TABLE: npt.NDArray[np.float64] = np.array(
    [
        [0.000, 4095.00, 0.002],
        [0.005, 2133.33, 0.003],
        [0.010, 1465.73, 0.007],
        [0.015, 601.46, 0.0406],
        [0.020, 383.84, 0.01472],
        [0.030, 234.93, 0.0241],
        [0.040, 158.03, 0.0287],
        [0.050, 120.00, 0.04225],
        [0.060, 104.09, 0.03065],
        [0.070, 67.19, 0.04897],
    ]
)
TABLE.setflags(write=False)

#: Distance (m) beyond which the response stays at the table's last value.
TABLE_RANGE: float = float(TABLE[-1, 0])
#: The largest raw value (the 12-bit ADC's full scale).
RAW_MAX: float = 4095.0

#: What a sensor reads with nothing in front of it (the table's last value, ≈67): the
#: ambient baseline the firmware's start-up calibration subtracts.
FAR_RAW: float = float(TABLE[-1, 1])

_D = np.ascontiguousarray(TABLE[:, 0])
_RAW = np.ascontiguousarray(TABLE[:, 1])
_SIGMA = np.ascontiguousarray(TABLE[:, 2])

#: The calibrated curve C(d) = T(d) − T(∞), at the table's distances (decreasing to 0).
CALIBRATED: npt.NDArray[np.float64] = _RAW - FAR_RAW
CALIBRATED.setflags(write=False)
# np.interp needs increasing x: the curve decreases, so its inverse reads it reversed
_C_UP = np.ascontiguousarray(CALIBRATED[::-1])
_D_UP = np.ascontiguousarray(_D[::-1])


def raw_from_distance(distance: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """Raw value for obstacle distances (m) from the sensor; ``inf`` gives the baseline."""
    return np.interp(np.asarray(distance, dtype=float), _D, _RAW)


def relative_sigma(distance: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """The real sensor's noise σ at ``distance``, as a fraction of the raw value."""
    return np.interp(np.asarray(distance, dtype=float), _D, _SIGMA)


def calibrated_from_distance(distance: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """Calibrated value C(d) = T(d) − T(∞) of obstacles at ``distance`` (m); 0 at and
    beyond 7 cm (and for ``inf``): what a robot sends with nothing in front of it.

    The inverse of :func:`distance_from_calibrated` for distances inside a profile's
    ``prox_max_distance``.
    """
    return np.interp(np.asarray(distance, dtype=float), _D, CALIBRATED)


def cutoff_value(max_distance: float) -> float:
    """The calibrated value at ``max_distance`` (m): a reading at or below it says
    "nothing within range"."""
    return float(np.interp(max_distance, _D, CALIBRATED))


def distance_from_calibrated(
    values: npt.ArrayLike, profile: RobotProfile
) -> npt.NDArray[np.float64]:
    """Calibrated IR values → distances (m), as a robot's software estimates them.

    The inverse of the calibrated curve, nominal: no gain correction, because a robot
    does not know how strongly each of its sensors answers (``puckboard calibrate ir``
    measures it). Values at or below ``C(profile.prox_max_distance)`` read
    ``profile.prox_range`` ("nothing"), the V-REP convention every record follows; no
    distance exceeds ``prox_range``; values above C(0) read 0 m. With the shipped
    ``epuck`` (``prox_max_distance`` = ``prox_range`` = 5 cm) a value of 53 or less means
    nothing. Vectorised: pass all 8 values at once.
    """
    return distances_from_calibrated(
        values, cutoff_value(profile.prox_max_distance), profile.prox_range
    )


def distances_from_calibrated(
    values: npt.ArrayLike,
    cutoff: npt.ArrayLike,
    nothing: npt.ArrayLike,
    out: npt.NDArray[np.float64] | None = None,
) -> npt.NDArray[np.float64]:
    """:func:`distance_from_calibrated` with its two numbers given: values at or below
    ``cutoff`` (see :func:`cutoff_value`) read ``nothing`` (m), and no distance exceeds it.
    Both may be arrays that broadcast against ``values`` (a simulator converts many
    robots' sensors at once, one column per robot); ``out``, when given, receives the
    distances (and is returned)."""
    v = np.asarray(values, dtype=np.float64)
    far = np.asarray(nothing, dtype=np.float64)
    if out is None:
        out = np.empty(np.broadcast_shapes(v.shape, far.shape))
    np.minimum(np.interp(v, _C_UP, _D_UP), far, out=out)
    np.copyto(out, far, where=v <= np.asarray(cutoff, dtype=np.float64))
    return out
