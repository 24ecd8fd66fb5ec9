"""The odometry filter fuses the gyro an adapter writes: end to end on the simulator."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from puckboard.backends.embedded import open_embedded
from puckboard.bench.estimation.trial import run_case
from puckboard.blackboard import Blackboard
from puckboard.estimation import GYRO_KEY, OdometrySource
from puckboard.records import AngularVelocity, Sensor, WheelEncoders
from puckboard.scenario.scene import Noise, RobotSpec, Scene


def _heading_errors(use_gyro: bool, *, seed: int = 5) -> tuple[float, int]:
    """Spin a slipping robot for 4 s; the estimate's final heading error and gyro reads."""
    scene = Scene("slip", robots=(RobotSpec("r", 0.0, 0.0, 0.0),), noise=Noise(wheel_speed=0.2))
    conn = open_embedded(scene, seed=seed)
    try:
        robot = conn.adapters["r"]
        robot.enable(Sensor.GYRO)
        source = OdometrySource(robot.ns, use_gyro=use_gyro, strict=True)
        robot.sense_all()  # the start pose: the estimate's origin
        source.step()
        robot.set_wheel_speeds(-2.0, 2.5)
        gyro_reads = 0
        for _ in range(80):
            robot.step()
            records = robot.sense_all()
            gyro_reads += isinstance(records.get(Sensor.GYRO), AngularVelocity)
            source.step()
        truth = robot.ns.value("pose").theta
        estimate = robot.ns.value("estimate/pose").theta
        return abs(math.remainder(estimate - truth, math.tau)), gyro_reads
    finally:
        conn.close()


def test_gyro_record_from_the_simulator_corrects_the_slipping_wheels() -> None:
    without, reads = _heading_errors(use_gyro=False)
    fused, _ = _heading_errors(use_gyro=True)
    assert reads == 80  # the adapter wrote an AngularVelocity record every cycle
    assert without > math.radians(5)  # 20 % slip: the counters lose the heading
    assert fused < 0.1 * without  # the gyro saw what the body did


def test_bench_compares_encoders_with_and_without_the_gyro() -> None:
    info, _ = run_case("line-follow", 0.1, 1, steps=120)
    (robot,) = info["robots"]
    assert robot["source_failures"] == 0
    plain = robot["encoders"]["max_heading_error_deg"]
    fused = robot["encoders + gyro"]["max_heading_error_deg"]
    assert plain > 0.5 and fused < 0.25 * plain
    biased, _ = run_case("line-follow", 0.1, 1, steps=120, gyro_bias=0.05)
    assert biased["robots"][0]["encoders + gyro"]["max_heading_error_deg"] > fused
    assert biased["robots"][0]["encoders"] == pytest.approx(robot["encoders"])  # bias: no draw


def _stand_then_drive(ns_name: str, board: Blackboard, **options: Any) -> OdometrySource:
    """2 s standing with a gyro offset of 0.01 rad/s (plus 1 s turned by hand), then 4 s
    driving straight: the offset is all the gyro says."""
    ns = board.namespace(ns_name)
    source = OdometrySource(ns, strict=True, **options)
    wheel = 0.0
    for i in range(120):
        t = i * 0.05
        # 40..59: carried round by hand: the wheels stand, the body turns
        rate = 1.0 if 40 <= i < 60 else 0.01
        if i >= 60:
            wheel += 0.2  # rad per step, both wheels: straight on
        ns.put("encoders", WheelEncoders(wheel, wheel), stamp=t)
        ns.put(GYRO_KEY, AngularVelocity(0.0, 0.0, rate), stamp=t)
        source.step()
    return source


def test_gyro_offset_is_learned_at_standstill_and_not_from_a_hand_turn() -> None:
    board = Blackboard(clock=lambda: 0.0)
    learning = _stand_then_drive("a", board)
    fixed = _stand_then_drive("b", board, bias_window=0)
    assert learning.gyro_bias == pytest.approx(0.01)
    assert fixed.gyro_bias == 0.0
    heading = learning.ns.value("estimate/pose").theta
    assert abs(heading) < 1e-6  # the offset removed, straight driving stays straight
    assert fixed.ns.value("estimate/pose").theta > 0.015  # 60 readings × 0.05 s × 0.01 rad/s
    with pytest.raises(ValueError, match="bias_window"):
        OdometrySource(bias_window=-1)


def test_bench_robots_that_settle_first_learn_the_gyro_offset() -> None:
    biased, _ = run_case("line-follow", 0.0, 1, steps=80, gyro_bias=0.02)
    settled, _ = run_case("line-follow", 0.0, 1, steps=80, gyro_bias=0.02, settle=2.0)
    (name,) = settled["gyro_bias_learned"]
    assert settled["gyro_bias_learned"][name] == pytest.approx(0.02)
    assert biased["gyro_bias_learned"][name] == 0.0  # never stood still
    worse = biased["robots"][0]["encoders + gyro"]["final_heading_error_deg"]
    better = settled["robots"][0]["encoders + gyro"]["final_heading_error_deg"]
    assert worse > 3.0 and better < 0.01


@pytest.mark.parametrize(("offset", "learned"), [(0.0, False), (0.01, True)])
def test_only_an_offset_that_stands_out_of_the_noise_is_subtracted(
    offset: float, learned: bool
) -> None:
    rng = np.random.default_rng(7)
    ns = Blackboard(clock=lambda: 0.0).namespace("r")
    source = OdometrySource(ns, strict=True)
    for i in range(100):  # 5 s standing, gyro noise σ 0.01 rad/s
        ns.put("encoders", WheelEncoders(0.0, 0.0), stamp=i * 0.05)
        rate = offset + 0.01 * float(rng.standard_normal())
        ns.put(GYRO_KEY, AngularVelocity(0.0, 0.0, rate), stamp=i * 0.05)
        source.step()
    if learned:
        assert source.gyro_bias == pytest.approx(offset, abs=0.004)  # within 4 σ/√n
    else:
        assert source.gyro_bias == 0.0  # a mean of pure noise is not taken for an offset
