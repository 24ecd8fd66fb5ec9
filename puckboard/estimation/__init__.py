"""Sensor interpretation and integration: estimators that run as knowledge sources.

* :class:`OdometryFilter` / :class:`OdometrySource`: a pose (x, y, θ) with covariance
  from the wheel encoders, an extended Kalman filter on filterpy, fused with a gyro and
  checked against the accelerometer where the robot has them;
* :class:`ProximityFilter` / :class:`ProximitySource`: per-sensor Kalman filters for
  the noisy IR distances, in plain numpy.

See ``docs/estimation.md`` for the model, the equations and how well it does against
the simulator's ground truth (``puckboard.estimation.bench``).
"""

from .odometry import OdometryFilter, OdometryNoise, wrap_angle
from .proximity import ProximityFilter
from .sources import GYRO_KEY, OdometrySource, ProximitySource

__all__ = [
    "GYRO_KEY",
    "OdometryFilter",
    "OdometryNoise",
    "OdometrySource",
    "ProximityFilter",
    "ProximitySource",
    "wrap_angle",
]
