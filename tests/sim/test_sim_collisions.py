"""Contacts: nothing overlaps after a step, nothing tunnels, each contact counts once."""

from __future__ import annotations

import logging
import math

import numpy as np
import pytest
from simworld_helpers import empty_scene, robot

from puckboard.profile import EPUCK2
from puckboard.scenario.scene import Arena, CircleObstacle, PolygonObstacle
from puckboard.sim.world import World

R = EPUCK2.body_radius
FULL = EPUCK2.max_wheel_speed


def polygon_distance(point, vertices) -> float:
    """Signed distance from a point to a convex polygon (negative inside)."""
    v = np.asarray(vertices, float)
    best = math.inf
    inside = True
    for k in range(len(v)):
        a, b = v[k], v[(k + 1) % len(v)]
        e = b - a
        w = np.asarray(point) - a
        t = min(max(np.dot(w, e) / np.dot(e, e), 0.0), 1.0)
        best = min(best, float(np.hypot(*(w - t * e))))
        if e[0] * w[1] - e[1] * w[0] < 0:  # right of a counter-clockwise edge
            inside = False
    return -best if inside else best


def test_driving_into_a_round_obstacle_stops_at_contact_and_counts_one_collision():
    post = CircleObstacle(0.3, 0.0, 0.03)
    w = World(empty_scene(robot("a"), obstacles=(post,)))
    w.set_wheel_speeds(0, FULL, FULL)
    for _ in range(120):
        w.step()
        assert math.hypot(w.poses[0, 0] - 0.3, w.poses[0, 1]) >= R + 0.03 - 1e-9
    assert w.collisions[0] == 1
    assert w.contacts_now[0]
    assert w.poses[0, 0] == pytest.approx(0.3 - 0.03 - R, abs=1e-6)


def test_driving_into_a_box_at_an_angle_slides_along_it_without_overlap():
    box = [[0.2, -0.3], [0.3, -0.3], [0.3, 0.3], [0.2, 0.3]]
    w = World(
        empty_scene(robot("a", 0.0, 0.0, math.radians(30)), obstacles=(PolygonObstacle(box),))
    )
    w.set_wheel_speeds(0, FULL, FULL)
    for _ in range(100):
        w.step()
        assert polygon_distance(w.poses[0, :2], box) >= R - 1e-9
    assert w.collisions[0] == 1
    assert w.poses[0, 1] > 0.1  # it slid up along the face


def test_two_robots_meeting_head_on_never_overlap_and_each_counts_once():
    w = World(empty_scene(robot("a", -0.2, 0.0, 0.0), robot("b", 0.2, 0.0, math.pi)))
    w.set_wheel_speeds(0, FULL, FULL)
    w.set_wheel_speeds(1, FULL, FULL)
    for _ in range(80):
        w.step()
        gap = math.hypot(*(w.poses[0, :2] - w.poses[1, :2]))
        assert gap >= 2 * R - 1e-9
    assert w.collisions.tolist() == [1, 1]
    assert w.contacts_now.tolist() == [True, True]


def test_arena_walls_keep_the_robot_inside():
    arena = Arena(-0.2, -0.2, 0.2, 0.2)
    w = World(empty_scene(robot("a", 0.0, 0.0, 0.7), arena=arena))
    w.set_wheel_speeds(0, FULL, FULL * 0.9)
    for _ in range(300):
        w.step()
        x, y, _ = w.poses[0]
        assert -0.2 + R - 1e-9 <= x <= 0.2 - R + 1e-9
        assert -0.2 + R - 1e-9 <= y <= 0.2 - R + 1e-9
    assert w.collisions[0] >= 1


def test_a_long_time_step_does_not_tunnel_through_a_thin_wall():
    wall = PolygonObstacle([[0.1, -0.2], [0.104, -0.2], [0.104, 0.2], [0.1, 0.2]])
    w = World(empty_scene(robot("a"), obstacles=(wall,), dt=0.6))  # 9 cm per step
    w.set_wheel_speeds(0, FULL, FULL)
    w.step(5)
    assert w.poses[0, 0] == pytest.approx(0.1 - R, abs=1e-6)
    assert w.collisions[0] == 1


def test_backing_off_and_hitting_again_counts_a_second_collision():
    post = CircleObstacle(0.2, 0.0, 0.03)
    w = World(empty_scene(robot("a"), obstacles=(post,)))
    w.set_wheel_speeds(0, FULL, FULL)
    w.step(60)
    w.set_wheel_speeds(0, -FULL, -FULL)
    w.step(10)
    assert not w.contacts_now[0]
    w.set_wheel_speeds(0, FULL, FULL)
    w.step(30)
    assert w.collisions[0] == 2


def test_a_robot_starting_inside_an_obstacle_is_moved_out():
    w = World(empty_scene(robot("a", 0.01, 0.0), obstacles=(CircleObstacle(0.0, 0.0, 0.02),)))
    assert math.hypot(*w.poses[0, :2]) == pytest.approx(R + 0.02)


def test_the_start_overlap_warning_names_the_robot_and_what_it_overlapped(caplog):
    """A robot moved at the start says which robot, out of what, and how far: a bare
    "a robot starts overlapping something" leaves the student to guess which line of
    the scene file is wrong."""
    wedge = PolygonObstacle(np.array([[0.3, -0.1], [0.5, -0.1], [0.4, 0.1]]), name="wedge")
    scene = empty_scene(
        robot("clear", -0.3, 0.0),
        robot("inside", 0.4, 0.0),
        robot("near_wall", 0.0, 0.49),
        robot("pair_a", 0.0, -0.3),
        robot("pair_b", 0.01, -0.3),
        obstacles=(wedge,),
        arena=Arena(-0.6, -0.5, 0.6, 0.5),
    )
    with caplog.at_level(logging.WARNING, logger="puckboard.sim.world"):
        World(scene)
    lines = {r.getMessage().split("robot ", 1)[1].split(" ", 1)[0]: r.getMessage()
             for r in caplog.records}  # fmt: skip
    assert set(lines) == {"'inside'", "'near_wall'", "'pair_a'", "'pair_b'"}, lines
    assert "starts overlapping obstacle 'wedge'; moved it" in lines["'inside'"]
    assert "starts overlapping the arena's wall; moved it" in lines["'near_wall'"]
    assert "starts overlapping robot 'pair_b'" in lines["'pair_a'"]
    assert "starts overlapping robot 'pair_a'" in lines["'pair_b'"]
    # how far it was moved, in cm: the robot at y = 0.49 ends at 0.5 - body radius
    moved_cm = float(lines["'near_wall'"].split("moved it ")[1].split(" cm")[0])
    assert moved_cm == pytest.approx(100 * (0.49 - (0.5 - R)), abs=0.05)
