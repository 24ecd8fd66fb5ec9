"""The estimators as knowledge sources: what they read and write on a robot's blackboard.

* :class:`OdometrySource` (sensor integration): ``encoders`` (+ ``acceleration``,
  ``gyro`` where the backend has them) → ``estimate/pose`` (a
  :class:`~puckboard.records.Pose` with ``ground_truth=False``), ``estimate/pose_cov``
  (3×3 covariance of x, y, θ) and ``estimate/slip`` (bool: the accelerometer says the
  wheels are not to be trusted just now);
* :class:`ProximitySource` (sensor interpretation): ``proximity`` →
  ``estimate/proximity`` (a :class:`~puckboard.records.Proximity` with filtered
  distances) and ``estimate/proximity_var`` (variance of each, m²).

Attach them like any knowledge source::

    OdometrySource.for_each_robot(episode.loop)   # one filter per robot, in the loop
    ProximitySource.for_each_robot(episode.loop)

A layer then reads ``frame.value("estimate/pose")``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from ..blackboard import Snapshot
from ..profile import EPUCK2, RobotProfile, get_profile
from ..records import Pose, Proximity, Sensor
from .knowledge import KnowledgeSource
from .odometry import OdometryFilter, OdometryNoise
from .proximity import ProximityFilter

if TYPE_CHECKING:
    from ..backends.base import RobotAdapter
    from ..blackboard import Namespace

__all__ = ["GYRO_KEY", "OdometrySource", "ProximitySource"]

GYRO_KEY = Sensor.GYRO.key
"""Key of a yaw-rate reading (rad/s, counter-clockwise): the
:class:`~puckboard.records.AngularVelocity` record adapters write under
``Sensor.GYRO`` (its ``z``), or a plain number on a board of your own. EPuckReal writes
it on an e-puck2; the embedded simulator once enabled (``robot.enable("gyro")``)."""


class OdometrySource(KnowledgeSource):
    """Pose estimate from wheel encoders with an EKF (:class:`OdometryFilter`).

    ``profile`` defaults to the robot's own profile when attached to a loop (else
    e-puck2). ``initial`` is the pose at the first encoder reading (default: the
    origin, so the estimate is relative to the start); ``initial_cov`` its covariance.
    ``use_accelerometer`` / ``use_gyro`` switch those fusions off for comparison.

    A gyro's offset is learned while the robot stands still: when the step counters have
    not moved, the body is not turning, so the gyro's reading is its offset plus noise.
    Readings within ``bias_gate`` (rad/s) of the running mean are averaged (over the last
    ``bias_window`` of them). The mean is subtracted from every reading as
    :attr:`gyro_bias` only once it differs from zero by more than three standard errors:
    the mean of a few noisy readings has an error of its own, σ/√n, which the heading
    would integrate as surely as an offset, so an offset too small to tell from the noise
    is left alone. The gate keeps a robot turned by hand from being learned as an offset
    (and assumes, as the e-puck2's start-up calibration makes true, an offset below it);
    a robot that never stops keeps that calibration alone. ``bias_window=0`` switches
    the learning off.

    ``encoders_key`` names the key holding the accumulated wheel angles, should they live
    elsewhere than ``encoders`` (a second, independent estimate, say).
    """

    reads = ("encoders", "acceleration", GYRO_KEY)
    writes = ("estimate/pose", "estimate/pose_cov", "estimate/slip")

    def __init__(
        self,
        ns: Namespace | None = None,
        *,
        profile: RobotProfile | str | None = None,
        noise: OdometryNoise | None = None,
        initial: Pose | tuple[float, float, float] = (0.0, 0.0, 0.0),
        initial_cov: Any = None,
        use_accelerometer: bool = True,
        use_gyro: bool = True,
        bias_window: int = 100,
        bias_gate: float = 0.05,
        encoders_key: str = "encoders",
        name: str | None = None,
        strict: bool = False,
    ) -> None:
        self.reads = (encoders_key, *type(self).reads[1:])  # type: ignore[misc]
        self._profile = None if profile is None else get_profile(profile)
        self.noise = noise if noise is not None else OdometryNoise()
        self.initial = initial
        self.initial_cov = initial_cov
        self.use_accelerometer = use_accelerometer
        self.use_gyro = use_gyro
        if bias_window < 0 or not bias_gate > 0:
            raise ValueError(
                f"bias_window must be >= 0 readings and bias_gate > 0 rad/s, got "
                f"{bias_window} and {bias_gate}"
            )
        self.bias_window = int(bias_window)
        self.bias_gate = float(bias_gate)
        #: The gyro offset (rad/s) learned at standstill, subtracted from each reading.
        self.gyro_bias = 0.0
        self._bias_samples = 0
        self._bias_mean = 0.0
        self._bias_var = 0.0
        self.filter = OdometryFilter(
            self.profile, self.noise, initial=initial, initial_cov=initial_cov
        )
        self._last: tuple[float, float, float] | None = None  # (stamp, left, right)
        self._last_speed: float | None = None
        super().__init__(ns, name=name, strict=strict)

    @property
    def profile(self) -> RobotProfile:
        return self._profile if self._profile is not None else EPUCK2

    def configure(self, robot: RobotAdapter) -> None:
        if self._profile is None and isinstance(getattr(robot, "profile", None), RobotProfile):
            self._profile = robot.profile

    def reset(self) -> None:
        self.filter = OdometryFilter(
            self.profile, self.noise, initial=self.initial, initial_cov=self.initial_cov
        )
        self._last = None
        self._last_speed = None
        self.gyro_bias = 0.0
        self._bias_samples = 0
        self._bias_mean = 0.0
        self._bias_var = 0.0

    def compute(self, inputs: Snapshot) -> Mapping[str, Any] | None:
        enc_rec = inputs.record(self.reads[0])
        assert enc_rec is not None  # the trigger
        enc, stamp = enc_rec.value, enc_rec.stamp
        flt = self.filter
        if self._last is not None:
            last_stamp, last_left, last_right = self._last
            dt = stamp - last_stamp
            d_left, d_right = enc.left - last_left, enc.right - last_right
            gyro = _yaw_rate(inputs.value(GYRO_KEY)) if self.use_gyro else None
            if gyro is not None:
                if d_left == 0.0 and d_right == 0.0:
                    self._learn_bias(gyro)
                gyro -= self.gyro_bias
            if self.use_accelerometer and dt > 0:
                self._check_slip(inputs, d_left, d_right, dt, stamp)
            flt.predict(d_left, d_right, gyro_rate=gyro, dt=dt)
        self._last = (stamp, enc.left, enc.right)
        return {
            "estimate/pose": flt.pose,
            "estimate/pose_cov": flt.cov,
            "estimate/slip": flt.slipping,
        }

    def _learn_bias(self, rate: float) -> None:
        """Fold a standstill reading into the offset's mean and variance (running, then
        exponential after ``bias_window`` readings); update :attr:`gyro_bias`."""
        if self.bias_window == 0:
            return
        delta = rate - self._bias_mean
        if abs(delta) > self.bias_gate:
            return  # turning although the wheels stand: pushed or carried, not an offset
        n = self._bias_samples = min(self._bias_samples + 1, self.bias_window)
        alpha = 1.0 / n
        self._bias_mean += alpha * delta
        self._bias_var = (1.0 - alpha) * (self._bias_var + alpha * delta * delta)
        if n >= 2:  # three standard errors of the mean (sample variance of n readings)
            significant = self._bias_mean**2 > 9.0 * self._bias_var / (n - 1)
            self.gyro_bias = self._bias_mean if significant else 0.0

    def _check_slip(
        self, inputs: Snapshot, d_left: float, d_right: float, dt: float, now: float
    ) -> None:
        """Compare the accelerometer with the acceleration the encoders imply."""
        speed, turn = self.profile.body_velocity(d_left / dt, d_right / dt)
        last_speed, self._last_speed = self._last_speed, speed
        acc = inputs.value("acceleration")
        if acc is None or last_speed is None:
            return  # no accelerometer on this backend (or not yet): nothing to compare
        implied = ((speed - last_speed) / dt, speed * turn)  # forward, centripetal (left)
        self.filter.check_slip((acc.x, acc.y), implied, now)


def _yaw_rate(value: Any) -> float | None:
    if value is None:
        return None
    rate = getattr(value, "z", value)
    try:
        rate = float(rate)
    except (TypeError, ValueError):
        return None
    return rate if math.isfinite(rate) else None


class ProximitySource(KnowledgeSource):
    """Filtered IR distances (:class:`ProximityFilter`); keyword arguments go to it."""

    reads = ("proximity",)
    writes = ("estimate/proximity", "estimate/proximity_var")

    def __init__(
        self,
        ns: Namespace | None = None,
        *,
        sigma: float = 0.002,
        accel_sigma: float = 0.1,
        gate: float = 4.0,
        name: str | None = None,
        strict: bool = False,
    ) -> None:
        self.settings = {"sigma": sigma, "accel_sigma": accel_sigma, "gate": gate}
        self.filter = ProximityFilter(8, **self.settings)
        self._last_stamp: float | None = None
        super().__init__(ns, name=name, strict=strict)

    def configure(self, robot: RobotAdapter) -> None:
        prox_range = getattr(getattr(robot, "profile", None), "prox_range", None)
        if prox_range:
            self.filter.range = float(prox_range)

    def reset(self) -> None:
        self.filter = ProximityFilter(8, range=self.filter.range, **self.settings)
        self._last_stamp = None

    def compute(self, inputs: Snapshot) -> Mapping[str, Any] | None:
        rec = inputs.record("proximity")
        assert rec is not None  # the trigger
        prox: Proximity = rec.value
        dt = 0.0 if self._last_stamp is None else max(rec.stamp - self._last_stamp, 0.0)
        self._last_stamp = rec.stamp
        filtered = self.filter.filter_record(prox, dt)
        return {
            "estimate/proximity": filtered,
            "estimate/proximity_var": np.array(self.filter.variance),
        }
