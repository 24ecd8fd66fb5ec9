"""The simulated gyro: the body's actual yaw rate, whatever the wheels claim."""

from __future__ import annotations

import math

import numpy as np
import pytest
from simworld_helpers import empty_scene, robot

from puckboard.backends.embedded import EmbeddedAdapter, open_embedded
from puckboard.errors import NotSupportedError
from puckboard.profile import EPUCK2
from puckboard.records import Sensor
from puckboard.scenario.scene import Arena, Noise
from puckboard.sim.world import World

SPIN = (-3.0, 3.0)  # rad/s, left/right: a counter-clockwise turn on the spot


def test_spinning_in_place_reads_the_true_turn_rate() -> None:
    world = World(empty_scene(robot()))
    world.set_wheel_speeds(0, *SPIN)
    expected = EPUCK2.body_velocity(*SPIN)[1]
    for _ in range(30):  # more than a full turn: the heading wraps on the way
        before = float(world.poses[0, 2])
        world.step()
        gyro = world.angular_velocities[0]
        turned = math.remainder(float(world.poses[0, 2]) - before, math.tau)
        assert gyro[2] == pytest.approx(expected, rel=1e-9)
        assert gyro[2] == pytest.approx(turned / world.dt, rel=1e-9)
        assert gyro[0] == 0.0 and gyro[1] == 0.0
    world.set_wheel_speeds(0, *SPIN[::-1])
    world.step()
    assert world.angular_velocities[0, 2] == pytest.approx(-expected)  # clockwise: negative


def test_driving_straight_reads_zero() -> None:
    world = World(empty_scene(robot(theta=0.7)))
    world.set_wheel_speeds(0, 5.0, 5.0)
    world.step(20)
    assert world.poses[0, 0] > 0.05  # it did move
    assert world.angular_velocities[0, 2] == 0.0


def test_gyro_follows_the_body_when_the_wheels_slip() -> None:
    # wheel slip: the counters count the commanded steps, the body turns by something else
    world = World(empty_scene(robot(), noise=Noise(wheel_speed=0.2)), seed=4)
    world.set_wheel_speeds(0, 2.0, 2.5)
    claimed = EPUCK2.body_velocity(2.0, 2.5)[1]
    errors = []
    for _ in range(50):
        before = float(world.poses[0, 2])
        world.step()
        turned = math.remainder(float(world.poses[0, 2]) - before, math.tau)
        assert world.angular_velocities[0, 2] == pytest.approx(turned / world.dt, rel=1e-9)
        errors.append(abs(world.angular_velocities[0, 2] - claimed))
    assert max(errors) > 0.1 * abs(claimed)  # the wheels' story and the body's differ


def test_contacts_push_a_robot_without_turning_it() -> None:
    # a pushes b along: b moves, its wheels stand still, its gyro reads zero
    world = World(empty_scene(robot("a", 0.0, 0.0, 0.0), robot("b", 0.08, 0.0, 0.4)))
    start = world.poses[1].copy()
    world.set_wheel_speeds(0, 6.0, 6.0)
    seen = []
    for _ in range(40):
        world.step()
        seen.append(world.angular_velocities[1, 2])
    assert world.poses[1, 0] - start[0] > 0.02 and world.collisions[1] >= 1
    assert seen == [0.0] * len(seen) and world.poses[1, 2] == start[2]


def test_a_round_robot_against_a_wall_still_turns() -> None:
    # pressed against a wall, the e-puck's round body turns freely on the spot
    arena = Arena(-0.2, -0.2, 0.2, 0.2)
    world = World(empty_scene(robot(x=0.2 - EPUCK2.body_radius - 0.001), arena=arena))
    world.set_wheel_speeds(0, 4.0, 4.0)
    world.step(10)
    assert world.contacts_now[0]
    world.set_wheel_speeds(0, *SPIN)
    world.step()
    assert world.contacts_now[0] or world.collisions[0] >= 1
    assert world.angular_velocities[0, 2] == pytest.approx(EPUCK2.body_velocity(*SPIN)[1])


def test_gyro_noise_scatters_the_reading_and_nothing_else() -> None:
    def run(sigma: float) -> tuple[np.ndarray, list[float]]:
        world = World(empty_scene(robot(), noise=Noise(gyro=sigma)), seed=9)
        world.set_wheel_speeds(0, 1.0, 2.0)
        readings = []
        for _ in range(400):
            world.step()
            readings.append(float(world.angular_velocities[0, 2]))
        return world.poses.copy(), readings

    clean_poses, clean = run(0.0)
    noisy_poses, noisy = run(0.05)
    assert np.array_equal(clean_poses, noisy_poses)  # the noise is the sensor's, not the body's
    error = np.array(noisy) - np.array(clean)
    assert abs(error.mean()) < 0.01
    assert error.std() == pytest.approx(0.05, rel=0.15)


def test_set_pose_resets_the_gyro() -> None:
    world = World(empty_scene(robot()))
    world.set_wheel_speeds(0, *SPIN)
    world.step()
    assert world.angular_velocities[0, 2] != 0.0
    world.set_pose(0, 0.1, 0.1, 1.0)
    assert world.angular_velocities[0, 2] == 0.0
    assert world.robot_arrays(0).angular_velocity.tolist() == [0.0, 0.0, 0.0]
    with pytest.raises(ValueError, match="read-only"):
        world.angular_velocities[0, 2] = 1.0


def test_embedded_robot_has_the_gyro_off_until_enabled() -> None:
    conn = open_embedded(empty_scene(robot("solo")))
    try:
        adapter = conn.adapters["solo"]
        assert isinstance(adapter, EmbeddedAdapter)
        assert Sensor.GYRO in adapter.available_sensors
        assert Sensor.GYRO not in adapter.enabled_sensors
        adapter.set_wheel_speeds(*SPIN)
        adapter.step()
        assert Sensor.GYRO not in adapter.sense_all()
        with pytest.raises(KeyError):
            adapter.ns.get("gyro")  # never written
        adapter.enable(Sensor.GYRO)
        gyro = adapter.sense_all()[Sensor.GYRO]
        assert gyro.z == pytest.approx(EPUCK2.body_velocity(*SPIN)[1])
        assert adapter.ns.value("gyro") is gyro
        assert adapter.refresh("gyro").z == gyro.z
        with pytest.raises(NotSupportedError, match="light"):
            adapter.enable(Sensor.LIGHT)
    finally:
        conn.close()


def test_gyro_bias_offsets_every_reading_without_a_draw() -> None:
    from puckboard.scenario.overrides import apply_scene_overrides

    scene = apply_scene_overrides(empty_scene(robot()), {"noise.gyro_bias": -0.01})
    assert scene.noise.gyro_bias == -0.01
    biased, clean = World(scene, seed=2), World(empty_scene(robot()), seed=2)
    for world in (biased, clean):
        world.set_wheel_speeds(0, 1.0, 2.0)
        world.step(5)
    assert biased.angular_velocities[0, 2] == pytest.approx(clean.angular_velocities[0, 2] - 0.01)
    assert np.array_equal(biased.poses, clean.poses)
    assert biased.rng.bit_generator.state == clean.rng.bit_generator.state
