"""Odometry as an extended Kalman filter: a pose (x, y, θ) *and how unsure we are of it*.

Why a filter at all, when dead reckoning is three lines? Because the three lines give a
pose that looks exact and is not. Every wheel increment carries a little error (noise
in the wheel's contact, a wheel radius or axle length a fraction of a millimetre off,
slip, a collision that stops the body while the wheels keep turning), and the errors
compound: a heading error of one degree becomes a lateral error of 1.7 cm per metre
driven. The filter keeps the same dead-reckoning mean but carries a covariance ``P``
alongside it, so a student sees the uncertainty grow as the robot drives, and a layer
can tell a trustworthy estimate from a stale guess.

Model (state ``x = [x, y, θ]``, world frame, θ counter-clockwise; inputs are the
encoder increments Δφ_l, Δφ_r in rad since the last step)::

    Δs_l = r·Δφ_l            Δs_r = r·Δφ_r              (wheel travel, m)
    Δs   = (Δs_r + Δs_l)/2   Δθ   = (Δs_r − Δs_l)/b     (b: axle length)
    μ    = θ + Δθ/2          c    = sin(Δθ/2)/(Δθ/2)    (the exact arc's chord factor)
    x'   = x + c·Δs·cos μ
    y'   = y + c·Δs·sin μ
    θ'   = θ + Δθ

    F = ∂x'/∂x = [[1, 0, −c·Δs·sin μ],        W = ∂x'/∂(Δs_l, Δs_r)
                  [0, 1,  c·Δs·cos μ],
                  [0, 0,  1         ]]
    Σ_w = diag(σ²(Δs_l), σ²(Δs_r)),   σ²(Δs) = k·|Δs| + (ε·Δs)²
    P'  = F·P·Fᵀ + W·Σ_w·Wᵀ

The process noise grows with wheel travel: standing still adds nothing, a metre driven
adds ``k`` m² per wheel. ``k`` covers random slip per metre; ``ε`` a relative speed noise
per step. The chord factor ``c`` makes a circle of known radius close on itself for
any step size, which matches the embedded simulator's exact arc integration.

**Why an EKF and not the linear heading/turn-rate filter.** A linear Kalman filter on
``[θ, ω, b_gyro]`` is cheaper and has no linearisation, but it estimates only the
heading: position would still be integrated outside the filter, with no covariance,
and the question "how far from home am I, give or take?" would have no answer. The
position errors are what grow fastest (they are driven by the heading error), and the
correlation between heading and lateral position is exactly what makes the ellipses
long and thin across the direction of travel. So the state is the full pose. The
motion model is nonlinear, and filterpy's ``ExtendedKalmanFilter.predict_x`` is linear
(``x = F·x + B·u``): filterpy's docstring says to override it when the state must be
computed otherwise, and that is the one way this filter uses filterpy. Its ``predict_x``
adds the motion model's step to the mean (and wraps the heading); each step sets the
Jacobian ``F`` and the process noise ``Q`` and calls filterpy's ``predict``, which
moves the mean and computes ``P = F P Fᵀ + Q``; filterpy's ``update`` with an
angle-wrapping residual fuses any absolute measurement (:meth:`OdometryFilter.correct`).
A predict costs about 0.1 ms, negligible against a 50 ms control period.

**Gyro** (e-puck2): the yaw rate enters as a second measurement of the same turn: the
turn Δθ used in the prediction is the inverse-variance weighted mean of the encoders'
and the gyro's, and its variance shrinks accordingly. A gyro does not slip, so it
catches turns the encoders miss; where there is no gyro, nothing changes.

**Accelerometer**: integrating it twice for position drifts within seconds on a small
robot. It is used for what it is good at: noticing that the body did not do what the
wheels claim. When the measured horizontal acceleration disagrees with the one implied
by the encoders (a bump, a push, slipping wheels), the filter flags *slip* for a short
hold time and adds the wheel travel itself to the wheel noise ("this travel may not
have happened"), so the covariance says honestly that the estimate just got worse.
Odometry cannot tell *how* the body moved during a collision; no amount of filtering
recovers that without an absolute measurement.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from ..profile import EPUCK2, RobotProfile
from ..records import Pose

__all__ = ["OdometryFilter", "OdometryNoise", "wrap_angle"]

FloatArray = npt.NDArray[np.float64]


def wrap_angle(angle: float) -> float:
    """An angle in [−π, π)."""
    return (angle + math.pi) % math.tau - math.pi


def _angle_residual(a: FloatArray, b: FloatArray) -> FloatArray:
    """Measurement residual a − b with the heading component wrapped (for filterpy)."""
    y = np.asarray(a, dtype=float) - np.asarray(b, dtype=float)
    flat = y.reshape(-1)  # a view: filterpy passes column vectors
    flat[2] = wrap_angle(float(flat[2]))
    return y


@functools.cache
def _pose_ekf() -> Any:
    """filterpy's EKF with the motion model's nonlinear mean (a class made on first use:
    filterpy, and scipy behind it, load only when a filter is built)."""
    from filterpy.kalman import ExtendedKalmanFilter

    class PoseEKF(ExtendedKalmanFilter):  # type: ignore[misc]
        """``predict(u)`` with ``u`` the motion model's step ``[Δx, Δy, Δθ]`` (3×1)."""

        x: FloatArray  # the state [x, y, θ] as a column, filterpy's own attribute

        def predict_x(self, u: FloatArray) -> None:
            self.x = self.x + u
            self.x[2, 0] = wrap_angle(float(self.x[2, 0]))

    return PoseEKF


@dataclass(frozen=True)
class OdometryNoise:
    """How unsure each wheel increment is, and how the other sensors are trusted.

    ``travel_variance`` (m²/m, the ``k`` above): variance added per metre a wheel
    travels; the default, 1e-5, is a 3 mm σ per wheel after a metre, typical of a
    calibrated e-puck on a smooth table. ``relative_sigma`` (the ``ε`` above): σ of a
    wheel's actual travel per step as a fraction of the measured travel; set it to the
    simulator's ``noise.wheel_speed`` when the encoders do not see that noise.
    ``gyro_sigma``: σ of the gyro's yaw rate (rad/s) per reading. ``slip_accel``: the
    disagreement (m/s²) between measured and encoder-implied horizontal acceleration
    beyond which the wheels are taken to slip; while they slip, each wheel's travel
    gets an extra σ of ``slip_fraction`` times that travel ("any of it may not have
    happened" at 1.0); ``slip_hold`` (s) is how long a slip flag lasts.
    """

    travel_variance: float = 1e-5
    relative_sigma: float = 0.0
    gyro_sigma: float = 0.01
    slip_accel: float = 0.25
    slip_fraction: float = 1.0
    slip_hold: float = 0.5

    def __post_init__(self) -> None:
        for name in (
            "travel_variance",
            "relative_sigma",
            "gyro_sigma",
            "slip_fraction",
            "slip_hold",
        ):
            value = getattr(self, name)
            if not math.isfinite(value) or value < 0:
                raise ValueError(f"OdometryNoise.{name} must be a finite number >= 0, got {value}")
        if not self.slip_accel > 0:
            raise ValueError(
                f"OdometryNoise.slip_accel must be positive m/s², got {self.slip_accel}"
            )

    def wheel_variance(self, travel: float) -> float:
        """σ² (m²) of one wheel's travel ``travel`` (m) in one step."""
        return self.travel_variance * abs(travel) + (self.relative_sigma * travel) ** 2


class OdometryFilter:
    """The pose EKF of the module docstring, fed encoder increments.

    ``profile`` gives the wheel radius and axle length (and the encoder resolution for
    :meth:`predict_steps`). ``initial`` is the starting pose (default: the origin,
    i.e. the estimate is relative to where the robot started) and ``initial_cov`` its
    3×3 covariance (default: zero, "we define the start").
    """

    def __init__(
        self,
        profile: RobotProfile = EPUCK2,
        noise: OdometryNoise | None = None,
        *,
        initial: Pose | tuple[float, float, float] = (0.0, 0.0, 0.0),
        initial_cov: npt.ArrayLike | None = None,
    ) -> None:
        self.profile = profile
        self.noise = noise if noise is not None else OdometryNoise()
        self.ekf = _pose_ekf()(dim_x=3, dim_z=3)
        self.reset(initial, initial_cov)
        #: True while the accelerometer says the wheels are not to be trusted.
        self.slipping = False
        self._slip_until = -math.inf

    def reset(
        self,
        initial: Pose | tuple[float, float, float] = (0.0, 0.0, 0.0),
        initial_cov: npt.ArrayLike | None = None,
    ) -> None:
        """Start again at ``initial`` with covariance ``initial_cov`` (default zero)."""
        if isinstance(initial, Pose):
            initial = (initial.x, initial.y, initial.theta)
        x, y, theta = (float(v) for v in initial)
        self.ekf.x = np.array([[x], [y], [wrap_angle(theta)]])
        cov = np.zeros((3, 3)) if initial_cov is None else np.array(initial_cov, dtype=float)
        if cov.shape != (3, 3) or not np.all(np.isfinite(cov)):
            raise ValueError(f"initial_cov must be a finite 3×3 matrix, got shape {cov.shape}")
        self.ekf.P = cov
        self.ekf.Q = np.zeros((3, 3))
        self.distance = 0.0  # m travelled by the robot's centre, for reports

    # -- the state ---------------------------------------------------------------------------
    @property
    def state(self) -> FloatArray:
        """``[x, y, θ]`` as a flat array (a copy)."""
        return self.ekf.x[:, 0].copy()

    @property
    def cov(self) -> FloatArray:
        """The 3×3 covariance of ``[x, y, θ]`` (a copy)."""
        return np.array(self.ekf.P, copy=True)

    @property
    def pose(self) -> Pose:
        """The estimate as a :class:`~puckboard.records.Pose` (``ground_truth=False``)."""
        x, y, theta = self.ekf.x[:, 0]
        return Pose(float(x), float(y), wrap_angle(float(theta)), ground_truth=False)

    # -- prediction --------------------------------------------------------------------------
    def predict(
        self,
        d_left: float,
        d_right: float,
        *,
        gyro_rate: float | None = None,
        dt: float | None = None,
    ) -> None:
        """Advance by wheel rotations ``d_left``, ``d_right`` (rad since the last call).

        ``gyro_rate`` (rad/s, counter-clockwise) and ``dt`` (s, the time the increments
        cover) fuse a gyro's yaw rate into the turn; leave them out without a gyro.
        """
        r, b = self.profile.wheel_radius, self.profile.axle_length
        ds_l, ds_r = r * d_left, r * d_right
        ds = (ds_r + ds_l) / 2.0
        dtheta = (ds_r - ds_l) / b

        var_l = self.noise.wheel_variance(ds_l)
        var_r = self.noise.wheel_variance(ds_r)
        if self.slipping:  # some of the wheels' travel may not have happened at all
            var_l += (self.noise.slip_fraction * ds_l) ** 2
            var_r += (self.noise.slip_fraction * ds_r) ** 2

        theta = float(self.ekf.x[2, 0])
        mu = theta + dtheta / 2.0
        cos_mu, sin_mu = math.cos(mu), math.sin(mu)
        W = np.array(
            [
                [cos_mu / 2 + ds * sin_mu / (2 * b), cos_mu / 2 - ds * sin_mu / (2 * b)],
                [sin_mu / 2 - ds * cos_mu / (2 * b), sin_mu / 2 + ds * cos_mu / (2 * b)],
                [-1.0 / b, 1.0 / b],
            ]
        )
        Q = W @ np.diag([var_l, var_r]) @ W.T

        if gyro_rate is not None and dt is not None and dt > 0:
            dtheta, Q = self._fuse_gyro(dtheta, Q, gyro_rate * dt, self.noise.gyro_sigma**2 * dt**2)
            mu = theta + dtheta / 2.0
            cos_mu, sin_mu = math.cos(mu), math.sin(mu)

        c = float(np.sinc(dtheta / (2.0 * math.pi)))  # sin(Δθ/2)/(Δθ/2)
        self.ekf.F = np.array(
            [
                [1.0, 0.0, -c * ds * sin_mu],
                [0.0, 1.0, c * ds * cos_mu],
                [0.0, 0.0, 1.0],
            ]
        )
        self.ekf.Q = Q
        # filterpy's predict: the nonlinear mean (PoseEKF.predict_x), then P = F P Fᵀ + Q
        self.ekf.predict(np.array([[c * ds * cos_mu], [c * ds * sin_mu], [dtheta]]))
        self.distance += abs(ds)

    def predict_steps(self, steps_left: float, steps_right: float, **kwargs: Any) -> None:
        """:meth:`predict` from motor step counts, as a real e-puck reports them."""
        rad = self.profile.rad_per_step
        self.predict(steps_left * rad, steps_right * rad, **kwargs)

    @staticmethod
    def _fuse_gyro(
        dtheta_enc: float, Q: FloatArray, dtheta_gyro: float, var_gyro: float
    ) -> tuple[float, FloatArray]:
        """Inverse-variance mean of two measurements of one turn; Q's θ row/column rescaled."""
        var_enc = float(Q[2, 2])
        if var_gyro <= 0:
            return dtheta_gyro, _scale_theta(Q, 0.0)
        if var_enc <= 0:  # the encoders claim certainty (noise model zero): keep them
            return dtheta_enc, Q
        weight = var_gyro / (var_enc + var_gyro)  # weight of the encoders
        fused = weight * dtheta_enc + (1.0 - weight) * dtheta_gyro
        return fused, _scale_theta(Q, weight)

    # -- other sensors -----------------------------------------------------------------------
    def check_slip(
        self,
        measured: tuple[float, float],
        implied: tuple[float, float],
        now: float,
    ) -> bool:
        """Compare measured horizontal acceleration (forward, left; m/s²) with the one the
        encoders imply; set :attr:`slipping` (held ``noise.slip_hold`` s). Returns it."""
        gap = math.hypot(measured[0] - implied[0], measured[1] - implied[1])
        if gap > self.noise.slip_accel:
            self._slip_until = now + self.noise.slip_hold
        self.slipping = now < self._slip_until
        return self.slipping

    def correct(self, pose: Pose | tuple[float, float, float], cov: npt.ArrayLike) -> None:
        """Fuse an absolute pose measurement (e.g. a landmark fix) with covariance ``cov``.

        This is filterpy's EKF update with ``H = I`` and the heading residual wrapped, so
        a measurement of 179° against an estimate of −179° is a 2° difference, not 358°.
        """
        if isinstance(pose, Pose):
            pose = (pose.x, pose.y, pose.theta)
        z = np.array([[float(v)] for v in pose])
        R = np.array(cov, dtype=float)
        if R.shape != (3, 3):
            raise ValueError(f"correct() needs a 3×3 measurement covariance, got {R.shape}")
        self.ekf.update(
            z, HJacobian=lambda x: np.eye(3), Hx=lambda x: x, R=R, residual=_angle_residual
        )
        self.ekf.x[2, 0] = wrap_angle(float(self.ekf.x[2, 0]))


def _scale_theta(Q: FloatArray, weight: float) -> FloatArray:
    """Q with the turn's variance scaled by ``weight`` (its covariances by the same)."""
    out = np.array(Q, copy=True)
    out[2, :2] *= weight
    out[:2, 2] *= weight
    out[2, 2] *= weight
    return out
