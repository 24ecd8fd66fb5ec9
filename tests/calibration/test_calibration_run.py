"""The calibration run on a simulated robot: what it recovers, what stops it, and that
the wheels are stopped however it ends.

The robot is the embedded simulator's, built with known gains and offsets and believing
it is the shipped ``epuck`` (as a real robot believes its profile), in the shipped
``calibration-wall`` scene with its noise: wheels that slip, noisy IR readings. The run
steps that world instead of waiting, so these tests take a second or two each.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from calibration_helpers import KNOWN_GAINS, KNOWN_OFFSETS, known_profile, wall_robot

from puckboard.backends.fake import FakeAdapter, FakeClock
from puckboard.calibration import WallModel, fit_all, make_plan, run_calibration
from puckboard.calibration.procedure import Odometry
from puckboard.errors import CalibrationError
from puckboard.profile import EPUCK
from puckboard.records import PROX_NAMES
from puckboard.scenario.scene import CircleObstacle

MODEL = WallModel(EPUCK)
#: A shorter plan than the default (6 mm steps: 11 stops), as the end-to-end test uses.
PLAN = make_plan(EPUCK, step=0.006)


def wheels_stopped(connection) -> bool:
    """Whether the robot's wheels are stopped: the adapter's last command, and the world's
    wheels once it steps."""
    adapter = connection.adapters["epuck"]
    connection.world.step(1)
    return adapter.wheels_stopped and not np.any(connection.world.wheel_speeds[0])


def test_the_fit_recovers_known_gains_and_offsets_on_a_slipping_noisy_robot():
    connection = wall_robot(known_profile(), seed=0)
    plan = make_plan(EPUCK)  # what a user runs: 21 stops
    measurements = run_calibration(connection.adapters["epuck"], plan, MODEL)
    fits = {f.sensor: f for f in fit_all(measurements.readings, MODEL)}
    assert set(fits) == set(KNOWN_GAINS)
    for name, fit in fits.items():
        assert fit.gain == pytest.approx(KNOWN_GAINS[name], rel=0.05), name
        assert fit.offset == pytest.approx(KNOWN_OFFSETS[name], abs=10.0), name
        assert fit.points >= 8 and fit.rms > 0  # noisy readings leave residuals
    assert wheels_stopped(connection)
    # 1 facing reading + 8 poses at each of the 21 stops, every one read 10 times
    assert len(measurements.readings) == 1 + 21 * 8
    assert {r.samples for r in measurements.readings} == {10}


def test_a_noise_free_robot_is_recovered_exactly():
    """No slip, no reading noise: the fit is against the very model that simulated it."""
    from puckboard.scenario.scene import Noise

    connection = wall_robot(known_profile(), noise=Noise())
    measurements = run_calibration(connection.adapters["epuck"], PLAN, MODEL)
    for fit in fit_all(measurements.readings, MODEL):
        assert fit.gain == pytest.approx(KNOWN_GAINS[fit.sensor], rel=1e-6)
        assert fit.offset == pytest.approx(KNOWN_OFFSETS[fit.sensor], abs=1e-3)


def test_each_stop_presents_every_sensor_straight_at_the_wall_from_its_distance():
    connection = wall_robot(None, seed=1)
    measurements = run_calibration(connection.adapters["epuck"], PLAN, MODEL)
    facing, *poses = measurements.readings
    assert facing.pose == "facing" and facing.heading == 0.0
    assert facing.distance == pytest.approx(EPUCK.body_radius)
    by_stop: dict[int, list] = {}
    for reading in poses:
        by_stop.setdefault(reading.stop, []).append(reading)
    assert sorted(by_stop) == list(range(PLAN.stops))
    for stop, readings in by_stop.items():
        assert sorted(r.pose for r in readings) == sorted(p.name for p in PLAN.presentations)
        for r in readings:
            # the step counters put it where the plan said, within the moves' tolerance
            assert r.backed == pytest.approx(PLAN.backs[stop], abs=0.001)
            target = next(p for p in PLAN.presentations if p.name == r.pose).heading
            assert np.cos(r.heading - target) > np.cos(np.radians(5))


def test_no_wall_in_front_stops_the_run_before_it_moves():
    connection = wall_robot(known_profile(), x=0.0)  # the middle of the arena
    with pytest.raises(CalibrationError, match="^no wall seen: .* place the robot touching"):
        run_calibration(connection.adapters["epuck"], PLAN, MODEL)
    assert wheels_stopped(connection)
    assert connection.world.poses[0][0] == pytest.approx(0.0)  # it never moved


class _StuckWheels(FakeAdapter):
    """A robot whose wheels do not turn: its step counters never change."""

    def _integrate(self, dt: float) -> None:
        pass


def test_wheels_that_do_not_turn_stop_the_run():
    robot = _StuckWheels(clock=FakeClock(0.05))
    robot.set_proximity(front_right=0.007, front_left=0.007)  # a wall, 7 mm ahead
    with pytest.raises(CalibrationError, match="^the wheels do not turn: .*switch the motors on"):
        run_calibration(robot, PLAN, MODEL)
    assert robot.wheels == (0.0, 0.0)
    assert robot.commands[-1][1:] == (0.0, 0.0)
    assert any(left or right for _, left, right in robot.commands)  # it did try to turn


def test_a_robot_held_against_the_wall_stops_the_run():
    """Its wheels turn (the step counters count) but something behind it holds it."""
    behind = CircleObstacle(x=0.263 - 0.037 - 0.0105, y=0.0, radius=0.01, name="post")
    connection = wall_robot(known_profile(), obstacles=(behind,))
    with pytest.raises(CalibrationError, match="^the robot does not move away from the wall: "):
        run_calibration(connection.adapters["epuck"], PLAN, MODEL)
    assert wheels_stopped(connection)


def test_a_sensor_that_does_not_respond_is_named():
    """Offsets far below zero: what a sensor calibrated with something in front of it
    sends, 0 whatever it sees."""
    dead = known_profile(ir_offset__right=-4000.0, ir_offset__rear_left=-4000.0)
    connection = wall_robot(dead)
    with pytest.raises(CalibrationError) as caught:
        run_calibration(connection.adapters["epuck"], PLAN, MODEL)
    message = str(caught.value)
    assert message.startswith("sensor right does not respond: it reads 0 presented to the wall")
    assert "; sensor rear_left does not respond" in message
    assert "switch it on with nothing within 10 cm" in message
    assert "\n" not in message
    assert wheels_stopped(connection)


def test_a_sensor_reading_full_scale_is_named():
    connection = wall_robot(known_profile(ir_offset__left=4095.0))
    with pytest.raises(CalibrationError, match="^sensor left reads full scale .4095. even turned"):
        run_calibration(connection.adapters["epuck"], PLAN, MODEL)
    assert wheels_stopped(connection)


def test_every_sensor_saturated_stops_at_the_first_reading():
    blinding = {f"ir_offset__{name}": 4095.0 for name in PROX_NAMES}
    connection = wall_robot(known_profile(**blinding))
    with pytest.raises(CalibrationError, match="^readings saturated: every sensor reads full"):
        run_calibration(connection.adapters["epuck"], PLAN, MODEL)
    assert connection.world.poses[0][0] == pytest.approx(0.263)


def test_ctrl_c_stops_the_wheels():
    connection = wall_robot(known_profile())
    seen = []

    def interrupt_on_the_third_pose(progress):
        seen.append(progress)
        if len(seen) == 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_calibration(
            connection.adapters["epuck"], PLAN, MODEL, progress=interrupt_on_the_third_pose
        )
    assert wheels_stopped(connection)
    assert [p.pose for p in seen] == ["facing", "front_right", "diagonal_right"]
    assert seen[-1].total == 1 + PLAN.stops * 8 and seen[-1].done == 2


def test_a_backend_without_step_counters_is_refused():
    connection = wall_robot(None)
    adapter = connection.adapters["epuck"]
    adapter.available_sensors = adapter.available_sensors - {
        s for s in adapter.available_sensors if s.value == "encoders"
    }
    with pytest.raises(CalibrationError, match="does not report encoders; calibrate ir needs"):
        run_calibration(adapter, PLAN, MODEL)


def test_odometry_counts_turns_cumulatively_and_distance_from_the_wall():
    odo = Odometry(EPUCK)
    odo.update(0.0, 0.0)
    full_turn = np.pi * EPUCK.axle_length / EPUCK.wheel_radius  # each wheel's rotation, rad
    odo.update(-full_turn, full_turn)
    assert odo.theta == pytest.approx(2 * np.pi)
    back = 0.01 / EPUCK.wheel_radius
    odo.update(-full_turn - back, full_turn - back)
    assert odo.backed == pytest.approx(0.01)
    assert odo.y == pytest.approx(0.0, abs=1e-12)


def test_the_readings_keep_their_spread_and_clipping():
    connection = wall_robot(known_profile(), seed=3)
    measurements = run_calibration(
        connection.adapters["epuck"], dataclasses.replace(PLAN, backs=PLAN.backs[:2]), MODEL
    )
    for r in measurements.readings:
        assert r.std.shape == (8,) and np.all(r.std >= 0)
        assert np.all(r.low <= r.samples) and np.all(r.high == 0)
        assert r.ambient is None  # the embedded simulator reports no ambient light
    # with the wall out of their reach, the left sensor (offset -10) reads 0 most of the
    # time, the right one (offset +20) never
    facing = measurements.readings[0]
    left, right = PROX_NAMES.index("left"), PROX_NAMES.index("right")
    assert facing.low[left] > facing.samples / 2 and facing.low[right] == 0
