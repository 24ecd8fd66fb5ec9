"""The judge on hand-made trajectories: known motions must get known verdicts.

The trajectories are built from the track's own geometry (arc length → point and
tangent), so a robot that "follows the line" here is exactly on it; swerves are smooth
lateral offsets to the robot's own left, as a pass right side to right side would be.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from puckboard.scenario import scene_from_dict
from puckboard.scenario.judge import FAILURES, Judge, JudgeRules

SPEED = 0.043  # m/s, the controllers' cruising speed
DT = 0.05


def pass_scene(**extra):
    data = {
        "name": "judge-test",
        "duration": 120.0,
        "goal": {"kind": "pass"},
        "track": {"shape": "stadium", "length": 0.8, "radius": 0.25, "width": 0.015},
        "robots": [
            {"name": "a", "track_distance": -0.25, "direction": "along"},
            {"name": "b", "track_distance": 0.25, "direction": "against"},
        ],
        "obstacles": [
            {"name": "east", "shape": "circle", "x": 0.2, "y": 0.25, "radius": 0.03},
            {"name": "west", "shape": "circle", "x": -0.2, "y": 0.25, "radius": 0.03},
        ],
    }
    data.update(extra)
    return scene_from_dict(data)


class TrackGeometry:
    """Point, tangent angle and left normal at arc length s of a closed track."""

    def __init__(self, track):
        seg = track.segments()
        self.a = seg[:, 0]
        self.d = seg[:, 1] - seg[:, 0]
        self.seglen = np.linalg.norm(self.d, axis=1)
        self.cum = np.concatenate([[0.0], np.cumsum(self.seglen)])
        self.length = float(self.cum[-1])

    def at(self, s):
        s = s % self.length
        i = min(int(np.searchsorted(self.cum, s, side="right") - 1), len(self.a) - 1)
        t = (s - self.cum[i]) / self.seglen[i]
        p = self.a[i] + t * self.d[i]
        heading = math.atan2(self.d[i][1], self.d[i][0])
        return p, heading


def bump(distance, full=0.10, zero=0.20):
    """1 within ``full`` of an event, falling linearly to 0 at ``zero``."""
    d = abs(distance)
    if d <= full:
        return 1.0
    if d >= zero:
        return 0.0
    return (zero - d) / (zero - full)


def line_pose(geo, s, sign, offset=0.0):
    """Pose at arc s, heading along (+1) or against (-1) the track, ``offset`` m to the
    robot's own left."""
    p, heading = geo.at(s)
    left = np.array([-math.sin(heading), math.cos(heading)]) * sign
    theta = heading if sign > 0 else heading + math.pi
    q = p + offset * left
    return (q[0], q[1], math.atan2(math.sin(theta), math.cos(theta)))


def feed(judge, pose_fn, duration, collisions_fn=None):
    """Call ``judge.update`` every DT until ``duration`` or a decision; returns the time of
    the decision, or for a failure the time the reported failure was detected."""
    steps = int(round(duration / DT))
    for k in range(steps + 1):
        t = k * DT
        poses = np.array(pose_fn(t))
        judge.update(t, poses, None if collisions_fn is None else collisions_fn(t))
        if judge.decided:
            return judge.failure_times.get(judge.failure, t)
    return judge.failure_times.get(judge.failure, duration) if judge.failure else duration


def head_on(geo, t):
    """Two robots 0.5 m apart on the line, driving towards each other at SPEED."""
    L = geo.length
    return [line_pose(geo, L - 0.25 + SPEED * t, 1), line_pose(geo, 0.25 - SPEED * t, -1)]


def wrapped_distance(s, e, length):
    d = (s - e) % length
    return min(d, length - d)


def test_a_clean_pass_is_a_success():
    scene = pass_scene()
    geo = TrackGeometry(scene.track)
    judge = Judge(scene)
    L = geo.length
    obstacle_arcs = [arc for _, arc in judge.track_obstacles]
    assert len(obstacle_arcs) == 2
    events = [0.0, L / 2, *obstacle_arcs]  # the two meeting points and the obstacles

    def poses(t):
        out = []
        for s0, sign in ((L - 0.25, 1), (0.25, -1)):
            s = s0 + sign * SPEED * t
            swerve = max(bump(wrapped_distance(s, e, L)) for e in events)
            out.append(line_pose(geo, s, sign, 0.08 * swerve))
        return out

    feed(judge, poses, 120.0)
    assert judge.decided and judge.success, (judge.failure, judge.events)
    assert judge.failure is None
    metrics = judge.metrics()
    for m in metrics:
        assert m.passed_other
        assert m.obstacles_passed == 2
        assert m.collisions == 0
        assert m.progress_laps > 0.5  # both went forward in their own direction
        assert 0.3 < m.on_line_fraction < 1.0
    kinds = [(e.robot, e.kind) for e in judge.events]
    assert ("a", "passed_other") in kinds and ("b", "passed_other") in kinds
    assert kinds.count(("a", "passed_obstacle")) == 2
    assert ("a", "left_line") in kinds and ("a", "back_on_line") in kinds


def test_driving_side_by_side_is_parallel_driving():
    scene = pass_scene()
    geo = TrackGeometry(scene.track)
    judge = Judge(scene)
    meet = (0.25 - 0.045) / SPEED  # the robots stop approaching 9 cm apart

    def poses(t):
        if t <= meet:
            return head_on(geo, t)
        # both turn to face +y (a turns left, b turns right: the same way seen from
        # above) within a second, then drive side by side
        turn = min(1.0, t - meet)
        drive = max(0.0, t - meet - 1.0) * SPEED
        a = (-0.045, -0.25 + drive, turn * math.pi / 2)
        b = (0.045, -0.25 + drive, math.pi - turn * math.pi / 2)
        return [a, b]

    t = feed(judge, poses, 60.0)
    assert judge.decided and not judge.success
    assert judge.failure == "parallel_driving"
    assert (
        meet + 1.0 + JudgeRules().parallel_s - 0.5
        <= t
        <= meet + 1.0 + JudgeRules().parallel_s + 1.5
    )
    assert not any(m.collisions for m in judge.metrics())
    assert judge.failures == ["parallel_driving"]


def test_a_touch_followed_by_side_by_side_driving_is_reported_as_parallel_driving():
    """The thesis's Figure 4.6: the robots touch, then drive off together the same way."""
    scene = pass_scene()
    geo = TrackGeometry(scene.track)
    judge = Judge(scene)
    touch = (0.5 - 0.070) / (2 * SPEED)  # centres 7 cm apart: the 3.7 cm bodies overlap
    at_touch = head_on(geo, touch)

    def after(dt):
        turn = min(1.0, dt)
        drive = max(0.0, dt - 1.0) * SPEED
        (ax, ay, _), (bx, by, _) = at_touch
        return [
            (ax - 0.01, ay + drive, turn * math.pi / 2),
            (bx + 0.01, by + drive, math.pi - turn * math.pi / 2),
        ]

    def poses(t):
        return head_on(geo, t) if t <= touch else after(t - touch)

    t = feed(judge, poses, 60.0)
    assert judge.failures == ["collision", "parallel_driving"]
    assert judge.failure == "parallel_driving" and judge.decided
    assert judge.failure_times["collision"] < judge.failure_times["parallel_driving"] == t
    kinds = [e.kind for e in judge.events]
    assert kinds.index("collision") < kinds.index("parallel_driving")


def test_a_touch_alone_is_a_collision_decided_after_the_watch():
    scene = pass_scene()
    geo = TrackGeometry(scene.track)
    judge = Judge(scene)
    touch = (0.5 - 0.070) / (2 * SPEED)  # centres 7 cm apart: the 3.7 cm bodies overlap
    rules = JudgeRules()

    def poses(t):  # after touching, both back away along the line: no side-by-side
        if t <= touch:
            return head_on(geo, t)
        return head_on(geo, max(0.0, touch - (t - touch)))

    decided_at = None
    for k in range(int(60.0 / DT) + 1):
        judge.update(k * DT, np.array(poses(k * DT)))
        if judge.decided:
            decided_at = k * DT
            break
    assert judge.failures[0] == "collision" and judge.failure == "collision"
    assert "parallel_driving" not in judge.failures
    assert decided_at == pytest.approx(judge.failure_times["collision"] + rules.failure_watch_s)


def test_following_the_line_backwards_is_turned_back():
    scene = pass_scene()
    geo = TrackGeometry(scene.track)
    judge = Judge(scene)
    L = geo.length
    turn_at = 2.0

    def poses(t):
        b = line_pose(geo, 0.25 - SPEED * t, -1)
        if t <= turn_at:
            return [line_pose(geo, L - 0.25 + SPEED * t, 1), b]
        s = L - 0.25 + SPEED * turn_at - SPEED * (t - turn_at)
        return [line_pose(geo, s, -1), b]  # a now heads back against its start direction

    t = feed(judge, poses, 60.0)
    assert judge.failure == "turned_back"
    assert judge.failure_robot == "a"
    assert t == pytest.approx(turn_at + JudgeRules().turn_back_m / SPEED, abs=0.2)
    a = judge.metrics()[0]
    assert a.progress_laps < 0


def test_stopping_is_stuck():
    scene = pass_scene()
    geo = TrackGeometry(scene.track)
    judge = Judge(scene)
    L = geo.length

    def poses(t):
        tt = min(t, 1.0)  # both stop after a second on the line
        return [line_pose(geo, L - 0.25 + SPEED * tt, 1), line_pose(geo, 0.25 - SPEED * tt, -1)]

    t = feed(judge, poses, 60.0)
    assert judge.failure == "stuck"
    rules = JudgeRules()
    # the window starts where the robot was still within stuck_distance of its stop
    assert t == pytest.approx(1.0 + rules.stuck_s - rules.stuck_distance / SPEED, abs=0.1)


def test_driving_head_on_is_a_geometric_collision():
    scene = pass_scene()
    geo = TrackGeometry(scene.track)
    judge = Judge(scene)

    def poses(t):
        return head_on(geo, t)

    t = feed(judge, poses, 60.0)
    assert judge.failure == "collision"
    # contact when the centres are one body diameter (7.4 cm) apart
    assert t == pytest.approx((0.5 - 0.074) / (2 * SPEED), abs=2 * DT)
    assert [m.collisions for m in judge.metrics()] == [1, 1]


def test_simulator_collision_counts_are_used_when_given():
    scene = pass_scene()
    geo = TrackGeometry(scene.track)
    judge = Judge(scene)

    def poses(t):
        return head_on(geo, t)

    t = feed(judge, poses, 10.0, collisions_fn=lambda t: [0, 1 if t >= 2.0 else 0])
    assert judge.failure == "collision" and judge.failure_robot == "b"
    assert t == pytest.approx(2.0)
    assert [m.collisions for m in judge.metrics()] == [0, 1]


def test_run_ending_before_the_meeting_is_not_passed():
    scene = pass_scene()
    geo = TrackGeometry(scene.track)
    judge = Judge(scene)

    def poses(t):
        return head_on(geo, t)

    feed(judge, poses, 3.0)
    assert not judge.decided
    judge.finish()
    assert judge.failure == "not_passed" and judge.success is False
    assert all(not m.passed_other for m in judge.metrics())
    # progress is measured in each robot's own starting direction
    for m in judge.metrics():
        assert m.progress_laps == pytest.approx(3.0 * SPEED / geo.length, rel=0.05)
        assert m.distance_m == pytest.approx(3.0 * SPEED, rel=0.01)


def follow_scene():
    return scene_from_dict(
        {
            "name": "follow-test",
            "goal": {"kind": "follow", "laps": 1.0},
            "track": {"shape": "circle", "radius": 0.3},
            "robots": [{"name": "solo", "track_position": 0.0, "direction": "along"}],
        }
    )


def test_follow_goal_succeeds_after_the_laps_and_counts_them():
    scene = follow_scene()
    geo = TrackGeometry(scene.track)
    judge = Judge(scene)
    speed = 0.1
    t = feed(judge, lambda t: [line_pose(geo, speed * t, 1)], 60.0)
    assert judge.success
    assert t == pytest.approx(geo.length / speed, abs=0.2)
    m = judge.metrics()[0]
    assert m.progress_laps == pytest.approx(1.0, abs=0.01)
    assert m.on_line_fraction == pytest.approx(1.0)


def test_driving_away_from_the_line_is_lost_line():
    scene = follow_scene()
    geo = TrackGeometry(scene.track)
    judge = Judge(scene)
    start = line_pose(geo, 0.0, 1)

    def poses(t):  # straight out of the circle, heading along the start tangent
        return [
            (
                start[0] + SPEED * t * math.cos(start[2]),
                start[1] + SPEED * t * math.sin(start[2]),
                start[2],
            )
        ]

    t = feed(judge, poses, 60.0)
    assert judge.failure == "lost_line"
    assert t > JudgeRules().lost_line_s


def test_avoid_goal_is_decided_at_the_end():
    scene = scene_from_dict(
        {
            "name": "avoid-test",
            "arena": {"xmin": -0.5, "ymin": -0.5, "xmax": 0.5, "ymax": 0.5},
            "robots": [{"name": "r", "x": 0.0, "y": 0.0, "theta": 0.0}],
        }
    )
    judge = Judge(scene)
    assert judge.goal == "avoid"
    feed(judge, lambda t: [(-0.3 + 0.02 * t, 0.0, 0.0)], 20.0)
    assert not judge.decided
    judge.finish()
    assert judge.success and judge.failure is None
    # and driving into the wall is a collision
    judge = Judge(scene)
    feed(judge, lambda t: [(0.3 + 0.02 * t, 0.0, 0.0)], 20.0)
    assert judge.failure == "collision"


def test_every_failure_name_is_documented():
    from pathlib import Path

    doc = (Path(__file__).parents[2] / "docs" / "scenarios.md").read_text(encoding="utf-8")
    for name in FAILURES:
        assert f"`{name}`" in doc, name


@pytest.mark.parametrize("near_line", [0.10, 0.01])
def test_on_line_and_progress_are_what_testing_every_segment_gives(near_line):
    """The judge follows each robot along the track testing only the segments that can
    be nearest (and skips its sensor point when the centre is far): every cycle's
    on-line verdict and every trusted arc position are those of the full search, here
    on wandering robots and with a near-line radius smaller than the sensors' offset."""
    rules = JudgeRules(near_line=near_line)
    judge = Judge(pass_scene(), rules=rules)
    rng = np.random.default_rng(5)
    poses = np.array([[-0.25, -0.25, 0.0], [0.25, -0.25, math.pi]])
    offsets = np.array([r.sensor_offset for r in judge.robots])
    on_line = np.zeros(2, dtype=int)
    for step in range(1500):
        poses[:, 2] += rng.normal(0.0, 0.2, size=2)
        poses[:, 0] += 0.004 * np.cos(poses[:, 2])
        poses[:, 1] += 0.004 * np.sin(poses[:, 2])
        judge.update(step * DT, poses)
        sensors = (
            poses[:, :2]
            + np.column_stack([np.cos(poses[:, 2]), np.sin(poses[:, 2])]) * offsets[:, None]
        )
        arc, dist, _ = judge.projector.project(np.vstack([poses[:, :2], sensors]))
        on_line += dist[2:] <= judge.on_line_tolerance
        for i, r in enumerate(judge.robots):
            assert r.near == (dist[i] <= near_line)
            if r.near:
                assert r.arc == arc[i]
    assert [r.on_line_cycles for r in judge.robots] == on_line.tolist()
    assert on_line.min() > 0 and on_line.max() < 1500  # on and off the line, both
