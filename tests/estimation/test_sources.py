"""The estimators as knowledge sources on a blackboard and in a control loop."""

from __future__ import annotations

import math

import numpy as np
import pytest

from puckboard.backends.fake import FakeAdapter, FakeClock
from puckboard.behaviours import Controller, Cruise
from puckboard.blackboard import Blackboard
from puckboard.control.loop import ControlLoop
from puckboard.estimation import GYRO_KEY, OdometrySource, ProximitySource
from puckboard.profile import EPUCK1
from puckboard.records import Acceleration, Pose, Proximity, WheelEncoders


def _fake_loop(profile=EPUCK1, speed=3.0):
    clock = FakeClock(dt=0.05)
    board = Blackboard(clock=lambda: clock.time)
    robot = FakeAdapter("epuck", profile=profile, blackboard=board, clock=clock)
    return ControlLoop([(robot, Controller([Cruise(speed)]))]), board, robot


def test_odometry_source_in_the_loop_tracks_the_fake_robot():
    loop, board, robot = _fake_loop()
    source = OdometrySource().attach(loop)
    assert source.profile is EPUCK1  # taken from the robot it was attached to
    loop.run(cycles=40, close=False)
    est = board.get("epuck/estimate/pose")
    truth = board.get("epuck/pose")
    assert est.stamp == truth.stamp == board.get("epuck/encoders").stamp
    assert isinstance(est.value, Pose) and not est.value.ground_truth
    assert est.value.x == pytest.approx(truth.value.x, abs=1e-12)
    assert est.value.x > 0.1
    cov = board.value("epuck/estimate/pose_cov")
    assert cov.shape == (3, 3) and cov[1, 1] > 0
    assert board.value("epuck/estimate/slip") is False
    loop.close()


def test_odometry_without_accelerometer_or_gyro_still_estimates():
    board = Blackboard(clock=lambda: 0.0)
    ns = board.namespace("r")
    source = OdometrySource(ns, initial=(1.0, 2.0, 0.0))
    for i in range(5):
        ns.put("encoders", WheelEncoders(i * 0.5, i * 0.5), stamp=i * 0.1)
        source.step()
    pose = ns.value("estimate/pose")
    assert (pose.x, pose.y) == pytest.approx((1.0 + 4 * 0.5 * source.profile.wheel_radius, 2.0))
    assert source.failures == 0


def test_gyro_key_is_fused_when_present():
    board = Blackboard(clock=lambda: 0.0)
    with_gyro, without = board.namespace("a"), board.namespace("b")
    sources = [OdometrySource(with_gyro), OdometrySource(without)]
    for i in range(10):
        for ns in (with_gyro, without):
            ns.put("encoders", WheelEncoders(i * 0.2, i * 0.2), stamp=i * 0.1)
        with_gyro.put(GYRO_KEY, 0.3, stamp=i * 0.1)  # the body turns; the wheels do not say so
        for s in sources:
            s.step()
    assert with_gyro.value("estimate/pose").theta > 0.1
    assert without.value("estimate/pose").theta == pytest.approx(0.0)


def test_accelerometer_disagreement_flags_slip():
    board = Blackboard(clock=lambda: 0.0)
    ns = board.namespace("r")
    source = OdometrySource(ns)
    for i in range(6):
        stamp = i * 0.05
        # wheels keep turning steadily; at i == 4 the body hits something and stops dead
        acc = Acceleration(-2.0 if i == 4 else 0.0, 0.0, 9.81)
        ns.put_many({"encoders": WheelEncoders(i * 0.2, i * 0.2), "acceleration": acc}, stamp=stamp)
        source.step()
        assert ns.value("estimate/slip") is (i >= 4)


def test_proximity_source_writes_filtered_record_and_variances():
    board = Blackboard(clock=lambda: 0.0)
    ns = board.namespace("r")
    source = ProximitySource(ns)
    rng = np.random.default_rng(1)
    for i in range(50):
        d = np.full(8, 0.05)
        d[7] = 0.02 + rng.normal(0.0, 0.002)
        ns.put("proximity", Proximity(d, np.zeros(8), 0.05), stamp=i * 0.05)
        source.step()
    est = ns.get("estimate/proximity")
    assert isinstance(est.value, Proximity)
    assert est.stamp == pytest.approx(49 * 0.05)
    assert est.value.front_left == pytest.approx(0.02, abs=0.003)
    assert not est.value.detected("front_right")
    var = ns.value("estimate/proximity_var")
    assert var[7] > 0 and var[0] == 0


def test_estimates_run_for_every_robot_of_a_loop():
    clock = FakeClock(dt=0.05)
    board = Blackboard(clock=lambda: clock.time)
    robots = [
        FakeAdapter("a", blackboard=board, clock=clock),
        FakeAdapter("b", blackboard=board, clock=clock, pose=(0.0, 0.0, math.pi / 2)),
    ]
    loop = ControlLoop([(r, Controller([Cruise(2.0)])) for r in robots])
    OdometrySource.for_each_robot(loop)
    ProximitySource.for_each_robot(loop)
    loop.run(cycles=10)
    a, b = board.value("a/estimate/pose"), board.value("b/estimate/pose")
    # each estimate is relative to its own start: both drove the same distance "forward"
    assert a.x == pytest.approx(b.x) and a.x > 0
    assert "a/estimate/proximity" in board.keys("a/estimate")
