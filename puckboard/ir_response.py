"""The IR proximity sensor's response curve: distance (m) → raw e-puck value.

The curve is the lookup table of Webots' ``E-puckDistanceSensor.proto``, which Cyberbotics
describe as the result of calibrations on a real e-puck. Webots interpolates it linearly
and, beyond its last entry (7 cm), keeps the last value (≈67): a real sensor never reads
exactly zero, because ambient reflections always return a little light. That baseline
is why the classic e-puck tutorials test ``value > 80`` for "something is there".

The table's third column is the real sensor's noise, a standard deviation expressed as a
fraction of the response; :func:`relative_sigma` interpolates it the same way.

Enki's analytic curve (``m(c − x0²)/(x² − 2·x0·x + c)``) agrees with this table within
about 30 % from 3 to 7 cm but is 60 % higher at 0.5 cm; the table is used because it is
measured, not fitted.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

__all__ = ["RAW_MAX", "TABLE", "TABLE_RANGE", "raw_from_distance", "relative_sigma"]

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

_D = np.ascontiguousarray(TABLE[:, 0])
_RAW = np.ascontiguousarray(TABLE[:, 1])
_SIGMA = np.ascontiguousarray(TABLE[:, 2])


def raw_from_distance(distance: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """Raw value for obstacle distances (m) from the sensor; ``inf`` gives the baseline."""
    return np.interp(np.asarray(distance, dtype=float), _D, _RAW)


def relative_sigma(distance: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """The real sensor's noise σ at ``distance``, as a fraction of the raw value."""
    return np.interp(np.asarray(distance, dtype=float), _D, _SIGMA)
