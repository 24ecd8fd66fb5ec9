"""The robot as built: the engine simulates each robot's truth (gains, offsets, wheels,
ground footprint, detection cut-off) while the adapters keep what the robot believes."""

from __future__ import annotations

import math

import numpy as np
import pytest
from simworld_helpers import empty_scene, robot
from test_sim_ir import PS0, PS7, obstacle_on_sensor_axis, wall_facing_sensor

from puckboard.backends.embedded import EmbeddedAdapter
from puckboard.ir_response import calibrated_from_distance, distance_from_calibrated
from puckboard.profile import EPUCK, EPUCK_VREP, apply_overrides
from puckboard.records import PROX_NAMES
from puckboard.scenario.scene import Track
from puckboard.sim.world import World

LEFT = PROX_NAMES.index("left")


def built(**changes: float):
    """The physical profile with ``changes`` ({path with '.' as '__': value})."""
    return apply_overrides(
        EPUCK, {k.replace("__", "."): v for k, v in changes.items()}, source="test"
    )


def world_of(profile, *obstacles, **kw) -> World:
    return World(empty_scene(robot("a", profile=profile), obstacles=obstacles), **kw)


def test_a_sensors_gain_scales_its_response_above_the_baseline():
    post = obstacle_on_sensor_axis(PS7, 0.02)
    nominal = world_of(EPUCK, post)
    weak = world_of(built(ir_gain__front_left=0.7), post)
    assert weak.prox_raw[0, PS7] == pytest.approx(0.7 * nominal.prox_raw[0, PS7], rel=1e-12)
    # a weaker sensor reads the same post as farther away: the robot does not know its gain
    assert nominal.prox_distance[0, PS7] < weak.prox_distance[0, PS7] < EPUCK.prox_range
    # and a free sensor still reads nothing: the firmware subtracted its own baseline
    free = world_of(built(ir_gain=1.3))
    assert (free.prox_raw[0] == 0.0).all()
    assert (free.prox_distance[0] == EPUCK.prox_range).all()


@pytest.mark.parametrize(("offset", "raw"), [(10.0, 10.0), (-10.0, 0.0), (60.0, 60.0)])
def test_an_offset_adds_to_the_calibrated_value(offset, raw):
    w = world_of(built(ir_offset__left=offset))
    assert w.prox_raw[0, LEFT] == raw  # clamped at 0, as the firmware does
    others = [k for k in range(8) if k != LEFT]
    assert (w.prox_raw[0, others] == 0.0).all()
    # 60 lies above the curve at 5 cm (53): a phantom obstacle, as on a badly calibrated robot
    expected = float(distance_from_calibrated(raw, EPUCK))
    assert w.prox_distance[0, LEFT] == expected
    assert (expected < EPUCK.prox_range) == (offset == 60.0)


def test_prox_max_distance_is_where_readings_turn_into_nothing():
    wall = wall_facing_sensor(PS0, 0.045)
    nominal = world_of(EPUCK, wall)
    short = world_of(built(prox_max_distance=0.04), wall)
    assert nominal.prox_raw[0, PS0] == short.prox_raw[0, PS0] > 0.0
    assert nominal.prox_distance[0, PS0] < EPUCK.prox_range
    assert short.prox_distance[0, PS0] == EPUCK.prox_range
    closer = world_of(built(prox_max_distance=0.04), wall_facing_sensor(PS0, 0.035))
    assert closer.prox_distance[0, PS0] < 0.04


def test_the_world_simulates_the_truth_and_the_adapter_keeps_the_belief():
    truth = built(ir_gain__front_left=0.5, body_radius=0.035)
    post = obstacle_on_sensor_axis(PS7, 0.02)
    scene = empty_scene(robot("a", profile=EPUCK, actual=truth), obstacles=(post,))
    w = World(scene)
    assert w.profiles[0] == EPUCK and w.actual[0] == truth
    nominal = world_of(EPUCK, post)
    assert w.prox_raw[0, PS7] == pytest.approx(0.5 * nominal.prox_raw[0, PS7], rel=1e-12)
    # odometry and conversions believe the profile, not the drawn truth
    assert EmbeddedAdapter(w, 0).profile == EPUCK


def test_each_wheel_rolls_its_own_true_radius_and_the_encoders_follow_the_command():
    truth = built(wheel_radius__left=0.0200, wheel_radius__right=0.0205)
    w = World(empty_scene(robot("a", profile=EPUCK, actual=truth)))
    omega, steps = 4.0, 100
    w.set_wheel_speeds(0, omega, omega)
    w.step(steps)
    t = steps * w.dt
    # the right wheel is larger: the robot curves left although both turn alike
    turn = (0.0205 - 0.0200) * omega / truth.axle_length
    assert w.poses[0, 2] == pytest.approx(turn * t, rel=1e-9)
    forward = (0.0200 + 0.0205) * omega / 2.0
    radius = forward / turn
    assert w.poses[0, 0] == pytest.approx(radius * math.sin(turn * t), rel=1e-9)
    # the steppers turned exactly as commanded: that is what encoders and speeds report
    assert w.encoders[0].tolist() == pytest.approx([omega * t, omega * t], rel=1e-12)
    assert w.wheel_speeds[0].tolist() == [omega, omega]
    # the believed robot, with two nominal wheels, would have driven straight
    straight = World(empty_scene(robot("a", profile=EPUCK)))
    straight.set_wheel_speeds(0, omega, omega)
    straight.step(steps)
    assert straight.poses[0, 2] == 0.0


EDGE = Track([[-1.0, 0.0], [1.0, 0.0]], width=0.012, closed=False)


def centre_readings(profile, **kw) -> list[float]:
    """The centre ground sensor as the robot moves across the line's edge."""
    values = []
    for y in np.arange(-0.012, 0.0, 0.0005):
        w = World(empty_scene(robot("a", 0.0, y, 0.0, profile=profile), track=EDGE), **kw)
        values.append(float(w.ground[0, 1]))
    return values


def test_the_ground_footprint_comes_from_the_profile():
    point = centre_readings(built(ground_footprint=0.0))
    wide = centre_readings(built(ground_footprint=0.004))
    floor, line = max(wide), min(wide)
    # a point sample jumps from floor to line at the edge; a 4 mm spot passes through
    # intermediate readings over 8 mm
    assert set(point) == {floor, line}
    between = [v for v in wide if line < v < floor]
    assert len(between) >= 10
    # the world's option, when given, replaces every profile's own
    assert centre_readings(built(ground_footprint=0.004), ground_footprint=0.0) == point


def test_recalibrating_next_to_an_obstacle_blinds_the_sensor_and_in_free_space_restores_it():
    wall = wall_facing_sensor(PS7, 0.02)
    w = world_of(built(ir_offset=5.0), wall)
    assert w.prox_distance[0, PS7] < EPUCK.prox_range
    w.recalibrate_ir(0)
    assert (w.prox_raw[0] == 0.0).all()
    assert (w.prox_distance[0] == EPUCK.prox_range).all()
    w.step()
    assert w.prox_raw[0, PS7] == 0.0  # the wall is now its baseline
    assert w.prox_raw[0, PS0] == pytest.approx(0.0, abs=1e-9)  # so is what ps0 saw of it
    w.set_pose(0, 1.0, 1.0, 0.0)  # far from the wall: below the new baseline, clamped
    assert (w.prox_raw[0] == 0.0).all()
    w.recalibrate_ir(0)
    # the 5 left over are gone
    assert w.sensing.ir["rays"].calibration.offset[0].tolist() == [0.0] * 8
    w.set_pose(0, 0.0, 0.0, 0.0)
    nominal = world_of(EPUCK, wall)
    assert w.prox_raw[0].tolist() == nominal.prox_raw[0].tolist()


def test_a_cone_robot_reports_what_a_calibrated_e_puck_would_send_for_its_distance():
    post = obstacle_on_sensor_axis(PS7, 0.02)
    w = world_of(EPUCK_VREP, post)
    seen = w.prox_distance[0] < EPUCK_VREP.prox_range
    assert seen.any()
    assert (
        w.prox_raw[0, seen].tolist() == calibrated_from_distance(w.prox_distance[0, seen]).tolist()
    )
    assert (w.prox_raw[0, ~seen] == 0.0).all()
    w.recalibrate_ir(0)  # a cone has no baseline to measure: nothing changes
    assert (
        w.prox_raw[0, seen].tolist() == calibrated_from_distance(w.prox_distance[0, seen]).tolist()
    )
