"""Measuring your own robot: ``puckboard calibrate ir`` as a plain, testable procedure.

* :mod:`~puckboard.calibration.plan`: where the robot stops and how it turns
  (:func:`make_plan`), and how long that takes.
* :mod:`~puckboard.calibration.response`: the simulator's own IR model in front of a
  wall (:class:`WallModel`), the response every fit is made against.
* :mod:`~puckboard.calibration.procedure`: the run on a robot adapter
  (:func:`run_calibration`): moves by the step counters, readings at every pose, wheels
  stopped however it ends; :mod:`~puckboard.calibration.readings`, what it reads.
* :mod:`~puckboard.calibration.checks`: what stops a run that cannot work, and says what
  to fix.
* :mod:`~puckboard.calibration.fit`: each sensor's gain and offset by least squares
  (:func:`fit_all`), with its residuals.
* :mod:`~puckboard.calibration.output`: the profile file and the report.
* :mod:`~puckboard.calibration.link`: ``puckboard calibrate link``, the link's round trips
  and cycles (:func:`~puckboard.calibration.link.measure_link`) and the profile file's
  ``[link]`` table.
"""

from __future__ import annotations

from .fit import SensorFit, fit_all, fit_sensor
from .output import ambient_light, calibrated_profile, profile_file_text
from .plan import CalibrationPlan, Presentation, make_plan
from .procedure import run_calibration
from .readings import Measurements, PoseReading, Progress
from .response import WallModel

__all__ = [
    "CalibrationPlan",
    "Measurements",
    "PoseReading",
    "Presentation",
    "Progress",
    "SensorFit",
    "WallModel",
    "ambient_light",
    "calibrated_profile",
    "fit_all",
    "fit_sensor",
    "make_plan",
    "profile_file_text",
    "run_calibration",
]
