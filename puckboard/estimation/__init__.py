"""Sensor interpretation and integration: estimators that run as knowledge sources.

* :class:`OdometryFilter` / :class:`OdometrySource`: a pose (x, y, θ) with covariance
  from the wheel encoders, an extended Kalman filter on filterpy, fused with a gyro and
  checked against the accelerometer where the robot has them;
* :class:`ProximityFilter` / :class:`ProximitySource`: per-sensor Kalman filters for
  the noisy IR distances, in plain numpy.

See ``docs/estimation.md`` for the model, the equations and how well it does against
the simulator's ground truth (``puckboard.bench.estimation``).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

__all__ = [
    "GYRO_KEY",
    "KnowledgeSource",
    "OdometryFilter",
    "OdometryNoise",
    "OdometrySource",
    "ProximityFilter",
    "ProximitySource",
    "wrap_angle",
]

# Loaded on first use, so that a knowledge source (``puckboard.estimation.knowledge``)
# can be imported without the filters, which pull in the robot profile and filterpy.
_LAZY = {
    "GYRO_KEY": "sources",
    "KnowledgeSource": "knowledge",
    "OdometryFilter": "odometry",
    "OdometryNoise": "odometry",
    "OdometrySource": "sources",
    "ProximityFilter": "proximity",
    "ProximitySource": "sources",
    "wrap_angle": "odometry",
}

if TYPE_CHECKING:  # pragma: no cover
    from .knowledge import KnowledgeSource
    from .odometry import OdometryFilter, OdometryNoise, wrap_angle
    from .proximity import ProximityFilter
    from .sources import GYRO_KEY, OdometrySource, ProximitySource


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{module}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(__all__)
