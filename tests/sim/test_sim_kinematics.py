"""Kinematics: exact arcs, wheel limits, encoders and the accelerometer."""

from __future__ import annotations

import math

import numpy as np
import pytest
from simworld_helpers import empty_scene, robot

from puckboard.profile import EPUCK2
from puckboard.sim.kinematics import arc, arc_step
from puckboard.sim.world import World


def make(theta: float = 0.0, dt: float = 0.05) -> World:
    return World(empty_scene(robot("a", 0.1, -0.2, theta), dt=dt))


def test_straight_line_distance_is_speed_times_time():
    w = make(theta=0.3)
    omega = 4.0
    w.set_wheel_speeds(0, omega, omega)
    w.step(40)
    x, y, theta = w.poses[0]
    travelled = math.hypot(x - 0.1, y + 0.2)
    assert travelled == pytest.approx(omega * EPUCK2.wheel_radius * 40 * w.dt, rel=1e-12)
    assert math.atan2(y + 0.2, x - 0.1) == pytest.approx(0.3)
    assert theta == pytest.approx(0.3)


def test_spin_in_place_keeps_the_position_and_turns_at_the_axle_rate():
    w = make()
    w.set_wheel_speeds(0, -2.0, 2.0)
    w.step(7)
    x, y, theta = w.poses[0]
    assert (x, y) == pytest.approx((0.1, -0.2), abs=1e-12)
    expected = 2 * 2.0 * EPUCK2.wheel_radius / EPUCK2.axle_length * 7 * w.dt
    assert theta == pytest.approx(math.remainder(expected, math.tau))


@pytest.mark.parametrize("dt", [0.01, 0.05, 0.25])
def test_arc_radius_is_exact_whatever_the_time_step(dt):
    left, right = 2.0, 4.0
    radius = EPUCK2.axle_length / 2 * (right + left) / (right - left)
    w = make(theta=0.0, dt=dt)
    w.set_wheel_speeds(0, left, right)
    centre = np.array([0.1, -0.2 + radius])  # to the left of a robot heading +x
    for _ in range(30):
        w.step()
        assert np.hypot(*(w.poses[0, :2] - centre)) == pytest.approx(radius, rel=1e-9)


def test_commands_are_clamped_to_the_profile_limit():
    w = make()
    w.set_wheel_speeds(0, 50.0, -50.0)
    w.step()
    assert w.wheel_speeds[0].tolist() == [EPUCK2.max_wheel_speed, -EPUCK2.max_wheel_speed]


def test_encoders_integrate_the_actual_wheel_rotation():
    w = make()
    w.set_wheel_speeds(0, 1.5, -0.5)
    w.step(10)
    w.set_wheel_speeds(0, 0.0, 2.0)
    w.step(10)
    assert w.encoders[0] == pytest.approx([1.5 * 0.5, -0.5 * 0.5 + 2.0 * 0.5])


def test_vectorised_arc_step_agrees_with_the_scalar_arc():
    poses = np.array([[0.0, 0.0, 0.0], [1.0, 2.0, 2.5], [-1.0, 0.5, -3.0]])
    forward = np.array([0.1, 0.05, -0.08])
    turn = np.array([0.0, 1.5, -4.0])
    delta = arc_step(poses, forward, turn, 0.05)
    for k in range(3):
        x, y, _ = arc(*poses[k], forward[k], turn[k], 0.05)
        assert (poses[k, 0] + delta[k, 0], poses[k, 1] + delta[k, 1]) == pytest.approx((x, y))


def test_accelerometer_reads_gravity_at_rest_and_the_speed_change_when_starting():
    w = make(theta=1.0)
    assert w.accelerations[0] == pytest.approx([0.0, 0.0, 9.81])
    w.set_wheel_speeds(0, 4.0, 4.0)
    w.step()
    v = 4.0 * EPUCK2.wheel_radius
    assert w.accelerations[0] == pytest.approx([v / w.dt, 0.0, 9.81])
    w.step()  # constant speed: no more acceleration
    assert w.accelerations[0, :2] == pytest.approx([0.0, 0.0], abs=1e-9)


def test_accelerometer_feels_the_centripetal_acceleration_to_the_left_in_a_left_turn():
    w = make(dt=0.01)
    w.set_wheel_speeds(0, 3.0, 5.0)
    w.step(50)
    v, omega = EPUCK2.body_velocity(3.0, 5.0)
    assert w.accelerations[0, 0] == pytest.approx(0.0, abs=1e-3)
    assert w.accelerations[0, 1] == pytest.approx(v * omega, rel=1e-3)
