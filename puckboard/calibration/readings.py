"""What a calibration run reads: one record per pose, the run's whole, its progress.

Plain data, shared by the run (:mod:`.procedure`), the checks that stop it
(:mod:`.checks`), the fit (:mod:`.fit`) and the report (:mod:`.output`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from .plan import CalibrationPlan

__all__ = ["Measurements", "PoseReading", "Progress"]

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]


@dataclass(frozen=True)
class PoseReading:
    """What the sensors read at one pose of the run.

    ``distance`` is the robot centre's distance from the wall and ``heading`` its turn
    from facing the wall (rad, counter-clockwise, cumulative over the run), both from the
    step counters. ``mean`` and ``std`` (sample standard deviation) are per sensor over
    ``samples`` readings, of which ``low`` were 0 and ``high`` full scale (clipped).
    ``ambient`` is the mean ambient light per sensor (0 bright .. 4095 dark) or ``None``
    where the backend does not report it.
    """

    stop: int
    pose: str
    sensors: tuple[str, ...]
    backed: float
    distance: float
    heading: float
    mean: FloatArray
    std: FloatArray
    samples: int
    low: IntArray
    high: IntArray
    ambient: FloatArray | None
    time: float


@dataclass(frozen=True)
class Measurements:
    """A finished run: the plan, every pose's reading, and how long it took (s)."""

    plan: CalibrationPlan
    readings: tuple[PoseReading, ...]
    seconds: float
    backend: str


@dataclass(frozen=True)
class Progress:
    """Where the run is, for a progress display: pose ``done + 1`` of ``total`` is being
    read, at stop ``stop`` (0-based) of ``stops``, ``backed`` m from touching."""

    stop: int
    stops: int
    backed: float
    pose: str
    sensors: tuple[str, ...]
    done: int
    total: int
