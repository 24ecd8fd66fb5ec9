"""The embedded adapter honours the adapter contract on top of a shared World."""

from __future__ import annotations

import math

import pytest
from simworld_helpers import empty_scene, pass_scene, robot

from puckboard.backends.embedded import EmbeddedAdapter, open_embedded
from puckboard.blackboard.store import MissingValueError
from puckboard.errors import NotSupportedError
from puckboard.records import Ground, Pose, Proximity, Sensor, WheelCommand
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
