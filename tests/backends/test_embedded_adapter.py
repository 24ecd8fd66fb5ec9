"""The embedded adapter honours the adapter contract on top of a shared World."""

from __future__ import annotations

import math

import numpy as np
import pytest
from simworld_helpers import empty_scene, noisy, pass_scene, robot

from puckboard.backends.embedded import EmbeddedAdapter, open_embedded
from puckboard.blackboard.store import MissingValueError
from puckboard.errors import NotSupportedError
from puckboard.records import (
    Acceleration,
    AngularVelocity,
    Ground,
    Pose,
    Proximity,
    Sensor,
    WheelCommand,
    WheelEncoders,
    WheelSpeeds,
)
from puckboard.sim.world import World


def test_open_embedded_builds_one_adapter_per_robot_sharing_the_world():
    conn = open_embedded(pass_scene(), seed=3)
    try:
        assert set(conn.adapters) == {"a", "b"}
        assert conn.stepper is conn.world
        assert all(a.stepper is conn.world for a in conn.adapters.values())
        assert all(a.blackboard is conn.blackboard for a in conn.adapters.values())
    finally:
        conn.close()


def test_sense_all_writes_records_to_the_robot_namespace():
    conn = open_embedded(pass_scene())
    a = conn.adapters["a"]
    a.sense_all()
    board = conn.blackboard
    assert isinstance(board.value("a/proximity"), Proximity)
    assert isinstance(board.value("a/ground"), Ground)
    pose = board.value("a/pose")
    assert isinstance(pose, Pose) and pose.ground_truth
    assert pose.x == pytest.approx(0.5)
    with pytest.raises(MissingValueError):  # b has not sensed yet
        board.value("b/pose")
    conn.close()


def test_records_carry_the_world_rows_exactly_and_keep_them_after_a_step():
    # a noisy world with the gyro's noise and bias too: every array is non-trivial
    conn = open_embedded(pass_scene(noisy()), seed=4)
    a = conn.adapters["b"]
    a.enable(Sensor.GYRO)
    world = conn.world
    i = world.index("b")
    a.set_wheel_speeds(3.0, 4.0)
    world.step(7)
    records = a.sense_all()
    assert set(records) == a.enabled_sensors
    prox, ground, pose = records[Sensor.PROXIMITY], records[Sensor.GROUND], records[Sensor.POSE]
    assert isinstance(prox, Proximity) and prox.range == a.profile.prox_range
    assert prox.distance.tolist() == world.prox_distance[i].tolist()
    assert prox.raw.tolist() == world.prox_raw[i].tolist()
    assert isinstance(ground, Ground)
    assert ground.value.tolist() == world.ground[i].tolist()
    assert ground.raw.tolist() == world.ground_raw[i].tolist()
    assert isinstance(pose, Pose) and pose.ground_truth
    assert [pose.x, pose.y, pose.theta] == world.poses[i].tolist()
    assert records[Sensor.ENCODERS] == WheelEncoders(*world.encoders[i].tolist())
    assert records[Sensor.WHEEL_SPEEDS] == WheelSpeeds(*world.wheel_speeds[i].tolist())
    assert records[Sensor.ACCELERATION] == Acceleration(*world.accelerations[i].tolist())
    assert records[Sensor.GYRO] == AngularVelocity(*world.angular_velocities[i].tolist())
    # a record handed out is the reading of its step, not a window on the world
    kept = prox.distance.copy(), pose
    world.step(5)
    assert world.poses[i].tolist() != [pose.x, pose.y, pose.theta]
    assert np.array_equal(prox.distance, kept[0]) and records[Sensor.POSE] is kept[1]
    assert not prox.distance.flags.writeable
    conn.close()


def test_a_controller_command_is_clamped_once_by_the_adapter_and_driven_as_sent(caplog):
    conn = open_embedded(empty_scene(robot("a")))
    a = conn.adapters["a"]
    limit = a.profile.max_wheel_speed
    within = WheelCommand(1.5, -2.0)
    assert a.command_wheels(within) is within  # nothing to change: the same object
    conn.world.step()
    assert conn.world.wheel_speeds[0].tolist() == [1.5, -2.0]
    with caplog.at_level("WARNING"):
        sent = a.command_wheels(WheelCommand(100.0, 1.0))
        a.command_wheels(WheelCommand(-100.0, 1.0))
    assert sent == WheelCommand(limit, 1.0)
    assert caplog.text.count("exceeds") == 1  # one warning per robot
    conn.world.step()
    assert conn.world.wheel_speeds[0].tolist() == [-limit, 1.0]
    conn.close()


def test_wheel_commands_are_clamped_and_stepping_moves_the_robot():
    conn = open_embedded(empty_scene(robot("a")))
    a = conn.adapters["a"]
    limit = a.profile.max_wheel_speed
    sent = a.set_wheel_speeds(100.0, -100.0)
    assert sent == WheelCommand(limit, -limit)
    a.set_wheel_speeds(2.0, 2.0)
    a.step(10)
    assert conn.world.time == pytest.approx(10 * conn.world.dt)
    pose = a.refresh(Sensor.POSE)
    assert pose.x == pytest.approx(2.0 * a.profile.wheel_radius * 10 * conn.world.dt)
    # the records carry simulation time as their stamp
    assert conn.blackboard.get("a/pose").stamp == pytest.approx(conn.world.time)
    conn.close()


def test_close_zeroes_the_wheels():
    conn = open_embedded(empty_scene(robot("a")))
    a = conn.adapters["a"]
    a.set_wheel_speeds(3.0, 3.0)
    conn.close()
    assert a.closed
    world = conn.world
    before = world.poses.copy()
    world.step(5)
    assert (world.poses == before).all()


def test_camera_goes_through_the_adapter_and_light_is_not_supported():
    conn = open_embedded(pass_scene())
    a = conn.adapters["a"]
    image = a.camera_image()
    assert image.pixels.shape == (39, 52, 3)
    assert conn.blackboard.value("a/camera") is image
    with pytest.raises(NotSupportedError):
        a.enable(Sensor.LIGHT)
    conn.close()


def test_adapter_for_a_missing_robot_index_is_refused():
    world = World(empty_scene(robot("a")))
    with pytest.raises(IndexError):
        EmbeddedAdapter(world, 1)


def test_controller_loop_runs_on_the_embedded_backend():
    from puckboard.behaviours import load_controller
    from puckboard.control.loop import ControlLoop

    conn = open_embedded(pass_scene())
    loop = ControlLoop([(ad, load_controller("improved")) for ad in conn.adapters.values()])
    loop.run(cycles=20)
    assert conn.world.step_count == 20
    assert all(ad.closed for ad in conn.adapters.values())
    assert math.isfinite(float(conn.world.poses.sum()))
