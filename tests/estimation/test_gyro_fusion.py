"""The odometry filter fuses the gyro an adapter writes: end to end on the simulator."""

from __future__ import annotations

import math

import pytest

from puckboard.adapters.embedded import open_embedded
from puckboard.estimation import GYRO_KEY, OdometrySource
from puckboard.estimation.bench import run_case
from puckboard.records import AngularVelocity, Sensor
from puckboard.sim.scene import Noise, RobotSpec, Scene


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


def test_the_gyro_key_is_the_record_key() -> None:
    assert Sensor.GYRO.key == GYRO_KEY


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
