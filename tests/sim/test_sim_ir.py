"""IR proximity: known geometry gives known raw values, and the distances they convert to.

A rays robot's ``raw`` is the calibrated value a real e-puck2 sends (the response above
the ambient baseline, clamped at 0) and its distance is that value through the one
conversion (:func:`puckboard.ir_response.distance_from_calibrated`): an estimate, as on
the robot, not the geometric distance.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from simworld_helpers import empty_scene, robot

from puckboard.ir_response import (
    FAR_RAW,
    TABLE,
    calibrated_from_distance,
    distance_from_calibrated,
    raw_from_distance,
)
from puckboard.profile import EPUCK2
from puckboard.records import PROX_NAMES
from puckboard.scenario.scene import CircleObstacle, Noise, PolygonObstacle
from puckboard.sim.world import World

PS7 = PROX_NAMES.index("front_left")
PS0 = PROX_NAMES.index("front_right")


def obstacle_on_sensor_axis(sensor: int, gap: float, radius: float = 0.02) -> CircleObstacle:
    """A round obstacle whose nearest point lies ``gap`` m straight out from ``sensor``
    of a robot at the origin heading +x."""
    pose = EPUCK2.prox_poses[sensor]
    cx = pose.x + (gap + radius) * math.cos(pose.heading)
    cy = pose.y + (gap + radius) * math.sin(pose.heading)
    return CircleObstacle(cx, cy, radius)


def wall_facing_sensor(sensor: int, gap: float) -> PolygonObstacle:
    """A wide flat box whose face is perpendicular to ``sensor``'s axis, ``gap`` away."""
    pose = EPUCK2.prox_poses[sensor]
    ux, uy = math.cos(pose.heading), math.sin(pose.heading)
    px, py = pose.x + gap * ux, pose.y + gap * uy  # a point on the face
    vx, vy = -uy, ux  # along the face
    corners = [
        (px - 0.05 * vx, py - 0.05 * vy),
        (px + 0.05 * vx, py + 0.05 * vy),
        (px + 0.05 * vx + 0.03 * ux, py + 0.05 * vy + 0.03 * uy),
        (px - 0.05 * vx + 0.03 * ux, py - 0.05 * vy + 0.03 * uy),
    ]
    return PolygonObstacle(corners)


@pytest.mark.parametrize("sensor", [PS7, PS0])
@pytest.mark.parametrize("gap", [0.007, 0.012, 0.03, 0.045])
def test_obstacle_at_a_known_distance_reads_about_that_distance(sensor, gap):
    w = World(empty_scene(robot("a"), obstacles=(obstacle_on_sensor_axis(sensor, gap),)))
    # the central ray sees the post at the gap, the outer rays a little farther (a round
    # post curves away): a little less light than the curve at the gap
    assert w.prox_raw[0, sensor] == pytest.approx(float(calibrated_from_distance(gap)), rel=0.02)
    assert w.prox_raw[0, sensor] < float(calibrated_from_distance(gap))
    # so the estimate lies a little beyond the gap, well within a millimetre
    assert gap < w.prox_distance[0, sensor] < gap + 0.001
    reach = w.profiles[0].prox_range
    # the sensor on the far side of the robot sees nothing
    assert w.prox_distance[0, (sensor + 4) % 8] == reach
    assert w.prox_raw[0, (sensor + 4) % 8] == 0.0


def test_every_distance_is_its_raw_value_through_the_one_conversion():
    post = obstacle_on_sensor_axis(PS7, 0.02)
    scene = empty_scene(
        robot("a"), robot("b", 0.1, 0.03, 2.5), obstacles=(post,), noise=Noise(proximity=0.05)
    )
    w = World(scene, seed=2)
    for _ in range(20):
        w.step()
        for i in range(2):
            expected = distance_from_calibrated(w.prox_raw[i], w.profiles[i])
            assert w.prox_distance[i].tolist() == expected.tolist()


def test_nothing_in_range_reads_exactly_the_range_and_zero():
    w = World(empty_scene(robot("a"), obstacles=(obstacle_on_sensor_axis(PS7, 0.08),)))
    assert (w.prox_distance[0] == EPUCK2.prox_range).all()
    # the firmware subtracted the ambient baseline it measured at start-up
    assert (w.prox_raw[0] == 0.0).all()


def test_an_obstacle_between_range_and_table_end_raises_raw_but_not_distance():
    w = World(empty_scene(robot("a"), obstacles=(wall_facing_sensor(PS7, 0.06),)))
    assert w.prox_distance[0, PS7] == EPUCK2.prox_range
    assert 0.0 < w.prox_raw[0, PS7] <= float(calibrated_from_distance(EPUCK2.prox_max_distance))


def test_raw_follows_the_calibrated_curve_for_a_flat_wall():
    for gap in (0.007, 0.01, 0.02, 0.03, 0.04):
        w = World(empty_scene(robot("a"), obstacles=(wall_facing_sensor(PS7, gap),)))
        # off-axis rays travel gap/cos(angle): a little further, a little less light
        curve = float(raw_from_distance(gap)) - FAR_RAW
        assert w.prox_raw[0, PS7] == pytest.approx(curve, rel=0.06)
        assert w.prox_raw[0, PS7] <= curve + 1e-9
        assert w.prox_distance[0, PS7] >= gap


def test_raw_falls_monotonically_with_distance():
    gaps = np.linspace(0.002, 0.075, 40)
    raws, distances = [], []
    for gap in gaps:
        w = World(empty_scene(robot("a"), obstacles=(wall_facing_sensor(PS0, gap),)))
        raws.append(w.prox_raw[0, PS0])
        distances.append(w.prox_distance[0, PS0])
    assert (np.diff(raws) <= 0).all()
    assert (np.diff(distances) >= 0).all()
    assert raws[0] > 2000 and raws[-1] == 0.0


def test_the_aperture_sees_an_obstacle_slightly_off_the_sensor_axis():
    # a thin post 6° off ps7's axis: one central ray would miss it, the aperture does not
    pose = EPUCK2.prox_poses[PS7]
    ang = pose.heading + math.radians(6.0)
    post = CircleObstacle(pose.x + 0.03 * math.cos(ang), pose.y + 0.03 * math.sin(ang), 0.002)
    w = World(empty_scene(robot("a"), obstacles=(post,)))
    assert w.prox_distance[0, PS7] < EPUCK2.prox_range
    # seen by the outer rays only, it answers weaker than a wall would at that distance
    assert 0.0 < w.prox_raw[0, PS7] < 0.5 * float(calibrated_from_distance(0.03))
    single = World(empty_scene(robot("a"), obstacles=(post,)), ir_rays=1)
    assert single.prox_distance[0, PS7] == EPUCK2.prox_range
    assert single.prox_raw[0, PS7] == 0.0


def test_a_robot_sees_another_robot_but_never_its_own_body():
    gap = 0.02
    scene = empty_scene(robot("a", 0.0, 0.0, 0.0), robot("b", 2 * 0.037 + gap, 0.0, math.pi))
    w = World(scene)
    front = [PS0, PS7]
    # the front sensors look 17° outwards, so their rays meet the other (round) body a
    # little further and at a slant: less light, a farther estimate, still within range
    for i in (0, 1):
        assert (w.prox_distance[i, front] < EPUCK2.prox_range).all()
        assert (w.prox_distance[i, front] > gap).all()
        assert (w.prox_distance[i, [2, 3, 4, 5]] == EPUCK2.prox_range).all()


def test_proximity_noise_perturbs_raw_values_but_not_an_empty_reading():
    w = World(empty_scene(robot("a"), noise=Noise(proximity=0.1)), seed=4)
    raws = []
    for _ in range(20):
        w.step()
        raws.append(w.prox_raw[0].copy())
        assert (w.prox_distance[0] == EPUCK2.prox_range).all()
    assert np.std(np.array(raws)[:, PS7]) > 1.0


def test_arena_walls_are_seen_along_the_closest_ray_of_the_aperture():
    from puckboard.scenario.scene import Arena

    arena = Arena(-0.5, -0.5, 0.5, 0.5)
    pose = EPUCK2.prox_poses[PS7]
    perpendicular = 0.03
    x = 0.5 - perpendicular - pose.x  # ps7 sits 3 cm ahead of the centre
    w = World(empty_scene(robot("a", x, 0.0, 0.0), arena=arena))
    # each of the 5 rays meets the wall at perpendicular / cos(its angle to the normal),
    # and the sensor reads their Gaussian-weighted response above the baseline
    half = EPUCK2.prox_aperture / 2
    offsets = np.linspace(-half, half, 5)
    weights = np.exp(-0.5 * (offsets / (EPUCK2.prox_aperture / 4)) ** 2)
    weights /= weights.sum()
    for sensor in (PS7, PS0):
        angles = EPUCK2.prox_poses[sensor].heading + offsets
        ray_lengths = perpendicular / np.cos(angles)
        expected = float((raw_from_distance(ray_lengths) * weights).sum()) - FAR_RAW
        assert w.prox_raw[0, sensor] == pytest.approx(expected, rel=1e-12)
    assert w.prox_distance[0, 4] == EPUCK2.prox_range  # rear_left faces away


def test_an_obstacle_touching_the_body_reads_the_sensors_depth_inside_the_outline():
    """The physical profile's sensors sit where Webots puts them, inside the 37 mm body
    (the calibration table's distances are from there): a touching obstacle reads the
    few millimetres between sensor and outline, and a high raw value."""
    pose = EPUCK2.prox_poses[PS7]
    heading = pose.heading
    reach = EPUCK2.body_radius + 0.02
    post = CircleObstacle(reach * math.cos(heading), reach * math.sin(heading), 0.02)
    w = World(empty_scene(robot("a"), obstacles=(post,)))
    assert w.contacts_now[0]
    depth = EPUCK2.body_radius - (pose.x * math.cos(heading) + pose.y * math.sin(heading))
    assert 0.004 < depth < 0.007
    assert w.prox_distance[0, PS7] == pytest.approx(depth, abs=5e-4)
    assert w.prox_raw[0, PS7] == pytest.approx(float(calibrated_from_distance(depth)), rel=0.05)


def test_a_robot_that_moves_out_of_reach_while_another_still_sees_reads_nothing():
    # Both robots see the post, then one is carried far away while the other still sees
    # it: only the near robot casts rays that step, and the far one must read the range
    # and nothing above the baseline, not what it saw the step before.
    post = obstacle_on_sensor_axis(PS7, 0.02)
    # b is a turned half a turn about the post, so its ps7 sees the post as a's does
    b = robot("b", 2 * post.x, 2 * post.y, math.pi)
    w = World(empty_scene(robot("a"), b, obstacles=(post,)))
    assert w.prox_distance[1, PS7] == pytest.approx(w.prox_distance[0, PS7], abs=1e-12)
    assert w.prox_distance[1, PS7] < EPUCK2.prox_range
    w.set_pose(1, 1.0, 1.0, 0.0)
    assert w.prox_distance[0, PS7] < EPUCK2.prox_range
    assert (w.prox_distance[1] == EPUCK2.prox_range).all()
    assert (w.prox_raw[1] == 0.0).all()


def test_a_far_robot_keeps_fresh_noise_while_another_robot_casts_rays():
    # with noise, a robot that sees nothing reads the baseline times (1 + sigma z) minus
    # the baseline, clamped at 0, with a new z each step; its raw values must not
    # random-walk away from 0
    post = obstacle_on_sensor_axis(PS7, 0.02)
    scene = empty_scene(
        robot("a"), robot("b", 1.0, 1.0, 0.0), obstacles=(post,), noise=Noise(proximity=0.05)
    )
    w = World(scene, seed=1)
    raws = []
    for _ in range(300):
        w.step()
        raws.append(w.prox_raw[1].copy())
        assert (w.prox_distance[1] == EPUCK2.prox_range).all()
    raws_array = np.array(raws)
    # sigma at 5 cm = sqrt(0.05² + 0.042²) ≈ 0.065: 6 sigma of the baseline bounds all
    assert raws_array.max() < 6 * 0.065 * TABLE[-1, 1]
    # fresh noise each step: about half the readings fall below the baseline and read 0
    assert 0.4 < (raws_array == 0.0).mean() < 0.6
