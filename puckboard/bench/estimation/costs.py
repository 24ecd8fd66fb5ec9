"""What the estimation filters cost per call, next to the alternatives they were chosen over.

The docs explain why the IR filter is written on plain floats rather than vectorised
with numpy or built from filterpy's ``KalmanFilter``; these are the measurements behind
that choice, each alternative computing the same equations. :class:`_VectorisedCV`
exists only to be timed.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

from ...estimation.odometry import OdometryFilter
from ...estimation.proximity import ProximityFilter
from ..timing import seconds_per_call

__all__ = ["measure_costs"]


def _median_us(fn: Any, calls: int = 2000) -> float:
    return seconds_per_call(fn, calls) * 1e6


def measure_costs() -> dict[str, float]:
    """Per-call costs (median µs of 5 repeats) behind the choices in the docs."""
    from filterpy.kalman import KalmanFilter

    odo = OdometryFilter()
    prox = ProximityFilter()
    z = np.full(8, 0.03)
    kfs = []
    for _ in range(8):
        kf = KalmanFilter(dim_x=2, dim_z=1)
        kf.F = np.array([[1.0, 0.05], [0.0, 1.0]])
        kf.H = np.array([[1.0, 0.0]])
        kf.R *= 4e-6
        kf.Q = np.diag([1e-9, 1e-4])
        kfs.append(kf)

    def filterpy_eight() -> None:
        for kf in kfs:
            kf.predict()
            kf.update(0.03)

    vec = _VectorisedCV(8)
    return {
        "odometry_predict_us": _median_us(lambda: odo.predict(0.1, 0.12)),
        "proximity_python_8_sensors_us": _median_us(lambda: prox.update(z, 0.05)),
        "proximity_numpy_vectorised_8_sensors_us": _median_us(lambda: vec.update(z, 0.05)),
        "proximity_filterpy_8_sensors_us": _median_us(filterpy_eight, calls=300),
    }


class _VectorisedCV:
    """The proximity filter's equations vectorised with numpy, only to measure the cost
    of that alternative (no gating or range handling beyond what costs the same)."""

    def __init__(self, n: int, var_z: float = 4e-6, var_a: float = 0.01) -> None:
        self.d = np.full(n, 0.03)
        self.rate = np.zeros(n)
        self.p00 = np.full(n, var_z)
        self.p01 = np.zeros(n)
        self.p11 = np.full(n, 0.09)
        self.var_z, self.var_a = var_z, var_a

    def update(self, z: npt.NDArray[np.float64], dt: float) -> npt.NDArray[np.float64]:
        dt2 = dt * dt
        d = self.d + self.rate * dt
        a = self.p00 + 2 * dt * self.p01 + dt2 * self.p11 + self.var_a * dt2 * dt2 / 4
        b = self.p01 + dt * self.p11 + self.var_a * dt2 * dt / 2
        c = self.p11 + self.var_a * dt2
        s = a + self.var_z
        y = z - d
        restart = y * y > 16.0 * s
        k0, k1 = a / s, b / s
        self.d = np.where(restart, z, np.clip(d + k0 * y, 0.0, 0.05))
        self.rate = np.where(restart, 0.0, self.rate + k1 * y)
        self.p00 = np.where(restart, self.var_z, (1 - k0) * a)
        self.p01 = np.where(restart, 0.0, (1 - k0) * b)
        self.p11 = np.where(restart, 0.09, c - k1 * b)
        return self.d.copy()
