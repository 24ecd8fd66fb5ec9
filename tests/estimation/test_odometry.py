"""The odometry EKF against motions whose answer is known in closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest

from puckboard.estimation import OdometryFilter, OdometryNoise, wrap_angle
from puckboard.profile import EPUCK1, EPUCK2
from puckboard.records import Pose

R = EPUCK2.wheel_radius
B = EPUCK2.axle_length


def test_straight_line_moves_x_by_r_dphi_and_keeps_y_and_theta():
    f = OdometryFilter(EPUCK2)
    for _ in range(40):
        f.predict(0.25, 0.25)
    x, y, theta = f.state
    assert x == pytest.approx(R * 0.25 * 40, rel=1e-12)
    assert y == pytest.approx(0.0, abs=1e-15)
    assert theta == pytest.approx(0.0, abs=1e-15)
    assert f.distance == pytest.approx(R * 10.0)


def test_straight_line_from_a_rotated_start_follows_the_heading():
    f = OdometryFilter(EPUCK1, initial=Pose(0.1, -0.2, math.radians(30)))
    f.predict(2.0, 2.0)
    x, y, theta = f.state
    s = EPUCK1.wheel_radius * 2.0
    assert (x, y) == pytest.approx((0.1 + s * math.cos(math.radians(30)), -0.2 + s * 0.5))
    assert theta == pytest.approx(math.radians(30))


def test_turning_on_the_spot_keeps_position_and_turns_by_r_dphi_over_axle():
    f = OdometryFilter(EPUCK2, initial=(0.3, 0.4, 0.0))
    d = 0.1  # rad per wheel per step, in opposite directions
    for _ in range(10):
        f.predict(-d, d)
    x, y, theta = f.state
    assert (x, y) == pytest.approx((0.3, 0.4), abs=1e-15)
    assert theta == pytest.approx(R * (10 * d - (-10 * d)) / B, rel=1e-12)


def test_heading_is_wrapped():
    f = OdometryFilter(EPUCK2, initial=(0.0, 0.0, 3.0))
    f.predict(-0.5, 0.5)  # turns left by r·1/b ≈ 0.39 rad, past +π
    assert -math.pi <= f.state[2] < math.pi
    assert f.state[2] == pytest.approx(wrap_angle(3.0 + R * 1.0 / B))


@pytest.mark.parametrize("steps", [8, 50, 400])
def test_circle_of_known_radius_closes_on_itself(steps):
    radius = 0.12  # m, of the centre's path
    omega = 0.4  # rad/s
    v = radius * omega
    left, right = EPUCK2.wheel_speeds(v, omega)
    period = math.tau / omega
    dt = period / steps
    f = OdometryFilter(EPUCK2, initial=(0.0, -radius, 0.0))
    farthest = 0.0
    for _ in range(steps):
        f.predict(left * dt, right * dt)
        farthest = max(farthest, math.hypot(*f.state[:2]))
        # every intermediate pose lies on the circle (exact arcs, whatever the step)
        assert math.hypot(*f.state[:2]) == pytest.approx(radius, rel=1e-9)
    x, y, theta = f.state
    assert (x, y) == pytest.approx((0.0, -radius), abs=1e-12)
    assert wrap_angle(theta) == pytest.approx(0.0, abs=1e-9)


def test_covariance_grows_without_corrections_and_not_when_standing_still():
    f = OdometryFilter(EPUCK2, OdometryNoise(travel_variance=1e-5, relative_sigma=0.02))
    traces = [np.trace(f.cov)]
    rng = np.random.default_rng(3)
    for _ in range(200):
        f.predict(*rng.uniform(0.0, 0.3, size=2))
        traces.append(np.trace(f.cov))
    assert np.all(np.diff(traces) > 0)
    assert np.all(np.linalg.eigvalsh(f.cov) >= -1e-15)  # still a covariance
    before = f.cov
    f.predict(0.0, 0.0)
    np.testing.assert_array_equal(f.cov, before)


def test_driving_straight_grows_lateral_uncertainty_more_than_along_track():
    """Heading error turns into sideways error: the ellipse gets long across the path."""
    f = OdometryFilter(EPUCK2)
    for _ in range(500):
        f.predict(0.2, 0.2)  # along +x, 2 m
    assert f.cov[1, 1] > 10 * f.cov[0, 0]
    assert f.cov[1, 2] > 0  # a left turn error moves the robot left: positive correlation


def test_noise_scales_with_travel():
    small = OdometryFilter(EPUCK2)
    large = OdometryFilter(EPUCK2)
    small.predict(0.1, 0.1)
    large.predict(0.4, 0.4)
    assert large.cov[2, 2] == pytest.approx(4 * small.cov[2, 2])


def test_gyro_pulls_the_turn_towards_it_and_shrinks_heading_variance():
    noise = OdometryNoise(travel_variance=1e-4, gyro_sigma=1e-3)
    plain = OdometryFilter(EPUCK2, noise)
    fused = OdometryFilter(EPUCK2, noise)
    plain.predict(0.2, 0.2)
    # wheels say straight, an accurate gyro says 0.05 rad/s for 1 s: the wheels slipped
    fused.predict(0.2, 0.2, gyro_rate=0.05, dt=1.0)
    assert plain.state[2] == pytest.approx(0.0)
    assert 0.04 < fused.state[2] <= 0.05
    assert fused.cov[2, 2] < plain.cov[2, 2]


def test_slip_flag_adds_the_wheel_travel_to_the_noise_and_expires():
    noise = OdometryNoise(slip_accel=1.0, slip_fraction=0.5, slip_hold=0.5)
    calm = OdometryFilter(EPUCK2, noise)
    bumped = OdometryFilter(EPUCK2, noise)
    assert not bumped.check_slip((0.1, 0.0), (0.0, 0.0), now=1.0)
    assert bumped.check_slip((-3.0, 0.0), (0.0, 0.0), now=1.0)  # a bump the wheels missed
    calm.predict(0.2, 0.2)
    bumped.predict(0.2, 0.2)
    travel = R * 0.2
    extra = 2 * (0.5 * travel) ** 2 / B**2  # both wheels' extra variance, seen as a turn
    assert bumped.cov[2, 2] == pytest.approx(calm.cov[2, 2] + extra)
    assert bumped.cov[2, 2] > 10 * calm.cov[2, 2]
    assert bumped.check_slip((0.0, 0.0), (0.0, 0.0), now=1.4)
    assert not bumped.check_slip((0.0, 0.0), (0.0, 0.0), now=1.6)


def test_correct_fuses_an_absolute_pose_and_wraps_the_heading():
    f = OdometryFilter(EPUCK2, initial=(0.0, 0.0, math.pi - 0.01), initial_cov=np.eye(3) * 0.01)
    f.correct(Pose(0.0, 0.0, -math.pi + 0.01), np.eye(3) * 0.01)  # 0.02 rad away, not 2π
    assert abs(wrap_angle(f.state[2] - math.pi)) < 0.011
    np.testing.assert_allclose(f.cov, np.eye(3) * 0.005)


def test_predict_steps_uses_the_encoder_resolution():
    a = OdometryFilter(EPUCK1)
    b = OdometryFilter(EPUCK1)
    a.predict_steps(1000, 1000)  # one revolution
    b.predict(math.tau, math.tau)
    np.testing.assert_allclose(a.state, b.state)


def test_bad_parameters_are_refused_with_the_field_named():
    with pytest.raises(ValueError, match="travel_variance"):
        OdometryNoise(travel_variance=-1.0)
    with pytest.raises(ValueError, match="initial_cov"):
        OdometryFilter(initial_cov=np.eye(2))


def test_a_step_is_filterpys_predict_with_the_motion_models_mean():
    """One way to use filterpy: its ``predict`` (nonlinear mean through ``predict_x``,
    then ``P = F P Fᵀ + Q`` with the step's ``F`` and ``Q``), priors kept as filterpy keeps them."""
    f = OdometryFilter(EPUCK2, initial=(0.0, 0.0, math.pi - 0.01), initial_cov=np.eye(3) * 1e-4)
    before = f.cov
    f.predict(1.0, 3.0)
    F, Q = f.ekf.F, f.ekf.Q
    assert np.array_equal(f.cov, F @ before @ F.T + Q)
    assert np.array_equal(f.ekf.x_prior, f.ekf.x) and np.array_equal(f.ekf.P_prior, f.ekf.P)
    assert -math.pi <= f.state[2] < math.pi  # the heading wrapped past ±π by predict_x
    assert f.state[2] != pytest.approx(math.pi - 0.01)
