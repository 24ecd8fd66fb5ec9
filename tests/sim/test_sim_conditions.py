"""Conditions in the engine: an obstacle's IR reflectance and the line's contrast change
what the sensors see, and their defaults change nothing."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from simworld_helpers import empty_scene, robot
from test_sim_broadphase import _random_swarm
from test_sim_ir import PS0, PS7, obstacle_on_sensor_axis, wall_facing_sensor

from puckboard.ir_response import FAR_RAW
from puckboard.profile import EPUCK, EPUCK_VREP
from puckboard.scenario.scene import Track
from puckboard.sim import broadphase as broadphase_module
from puckboard.sim.world import World


def raw_response(*obstacles, profile=EPUCK) -> np.ndarray:
    """Every sensor's response (before the firmware's calibration) of a robot at the origin."""
    world = World(empty_scene(robot("a", profile=profile), obstacles=obstacles))
    return world.sensing.ir["rays"].proximity.response(world.poses.tolist())[0]


@pytest.mark.parametrize("make", [lambda: obstacle_on_sensor_axis(PS7, 0.015),
                                  lambda: wall_facing_sensor(PS0, 0.015)])  # fmt: skip
def test_reflectance_scales_the_light_an_obstacle_returns_above_the_baseline(make):
    seen = make()
    white = raw_response(seen)
    dark = raw_response(dataclasses.replace(seen, ir_reflectance=0.25))
    unseen = raw_response(dataclasses.replace(seen, ir_reflectance=0.0))
    sensor = int(np.argmax(white))
    baseline = raw_response()[sensor]
    assert white[sensor] > baseline
    assert dark[sensor] - baseline == pytest.approx(0.25 * (white[sensor] - baseline), rel=1e-9)
    assert unseen[sensor] == pytest.approx(baseline, rel=1e-12)
    assert baseline == pytest.approx(FAR_RAW * EPUCK.ir_gain[sensor], rel=1e-12)


def test_a_dark_obstacle_still_hides_a_light_one_behind_it():
    behind = obstacle_on_sensor_axis(PS7, 0.03)
    front = dataclasses.replace(
        obstacle_on_sensor_axis(PS7, 0.01, radius=0.005), ir_reflectance=0.0
    )
    assert raw_response(behind)[PS7] > raw_response(front, behind)[PS7]
    assert raw_response(front, behind)[PS7] == pytest.approx(raw_response()[PS7], rel=1e-9)


def test_reflectance_one_is_exactly_the_model_without_it():
    post = obstacle_on_sensor_axis(PS7, 0.02)
    assert (raw_response(post) == raw_response(dataclasses.replace(post, ir_reflectance=1.0))).all()


def test_v_rep_cone_sensors_see_any_object_alike():
    post = obstacle_on_sensor_axis(PS7, 0.02)
    scene = lambda ob: empty_scene(robot("a", profile=EPUCK_VREP), obstacles=(ob,))  # noqa: E731
    light = World(scene(post)).prox_distance[0]
    dark = World(scene(dataclasses.replace(post, ir_reflectance=0.1))).prox_distance[0]
    assert (light == dark).all()
    assert light[PS7] < EPUCK_VREP.prox_range


def ground_under(contrast: float) -> tuple[float, float]:
    """(centre sensor on the line, on the floor) for a line of ``contrast``."""
    line = Track([[-1.0, 0.0], [1.0, 0.0]], width=0.015, closed=False, contrast=contrast)
    on = World(empty_scene(robot("a", -EPUCK.ground_poses[1].x, 0.0, 0.0), track=line))
    off = World(empty_scene(robot("a", -EPUCK.ground_poses[1].x, 0.2, 0.0), track=line))
    return float(on.ground[0, 1]), float(off.ground[0, 1])


def test_line_contrast_moves_the_line_towards_the_floor():
    full_line, floor = ground_under(1.0)
    half_line, floor_again = ground_under(0.5)
    none_line, _ = ground_under(0.0)
    assert floor == floor_again
    assert half_line == pytest.approx(floor - 0.5 * (floor - full_line), rel=1e-9)
    assert none_line == pytest.approx(floor, rel=1e-12)


def test_dark_obstacles_read_the_same_through_either_broad_phase(monkeypatch):
    swarm = _random_swarm(26, 7)
    dark = dataclasses.replace(
        swarm, obstacles=tuple(dataclasses.replace(o, ir_reflectance=0.3) for o in swarm.obstacles)
    )
    results = []
    for scene in (swarm, dark):
        for limit in (0, 1000):  # vectorised, then plain Python
            monkeypatch.setattr(broadphase_module, "PYTHON_BROAD_PHASE_MAX", limit)
            world = World(scene, seed=2)
            for i in range(26):
                world.set_wheel_speeds(i, 4.0 + 0.1 * i, 5.0 - 0.1 * i)
            seen = []
            for _ in range(8):  # a robot starts beside the west post
                world.step(1)
                seen.append(world.prox_raw.copy())
            results.append(np.array(seen))
    light_numpy, light_python, dark_numpy, dark_python = results
    assert np.array_equal(dark_numpy, dark_python)
    assert np.array_equal(light_numpy, light_python)
    assert not np.array_equal(light_numpy, dark_numpy)  # the obstacles are seen, and darker
