"""The gyro record, its key, and the adapters' opt-in sensors."""

from __future__ import annotations

import math

import pytest

from puckboard.backends.base import RobotAdapter
from puckboard.backends.fake import FakeAdapter
from puckboard.blackboard import Blackboard
from puckboard.records import RECORD_TYPES, AngularVelocity, Sensor
from puckboard.viz.monitor import format_value


def test_gyro_record_is_finite_checked_and_frozen() -> None:
    w = AngularVelocity(0.0, 0.0, 1.5)
    assert w.z == 1.5
    with pytest.raises(ValueError, match=r"AngularVelocity\.z must be a finite number"):
        AngularVelocity(0.0, 0.0, math.nan)
    with pytest.raises(ValueError, match=r"AngularVelocity\.x"):
        AngularVelocity(math.inf, 0.0, 0.0)
    with pytest.raises(ValueError, match=r"AngularVelocity\.y"):
        AngularVelocity(0.0, "fast", 0.0)  # type: ignore[arg-type]
    with pytest.raises(AttributeError):
        w.z = 2.0  # type: ignore[misc]


def test_gyro_key_is_declared_for_every_robot() -> None:
    assert RECORD_TYPES[Sensor.GYRO] is AngularVelocity
    fake = FakeAdapter("r", blackboard=Blackboard())
    with pytest.raises(ValueError, match="AngularVelocity"):
        fake.ns.put("gyro", 1.5)  # a bare number is refused: the key holds records
    assert "rad/s" in format_value(AngularVelocity(0.0, 0.0, 0.25))


def test_fake_robot_reports_its_ideal_turn_rate() -> None:
    fake = FakeAdapter()
    assert Sensor.GYRO in fake.enabled_sensors  # the base default: only the camera is opt-in
    fake.set_wheel_speeds(-2.0, 3.0)
    gyro = fake.sense_all()[Sensor.GYRO]
    assert gyro.z == pytest.approx(fake.profile.body_velocity(-2.0, 3.0)[1])
    assert gyro.z > 0  # right wheel faster: a counter-clockwise turn
    before = fake.theta
    fake.step()
    assert fake.theta - before == pytest.approx(gyro.z * fake.clock.dt)


def test_opt_in_sensors_start_disabled_until_enabled() -> None:
    class Quiet(FakeAdapter):
        opt_in_sensors = frozenset({Sensor.CAMERA, Sensor.GYRO, Sensor.LIGHT})

    quiet = Quiet()
    assert not quiet.enabled_sensors & {Sensor.CAMERA, Sensor.GYRO, Sensor.LIGHT}
    assert Sensor.GYRO not in quiet.sense_all()
    quiet.enable("gyro")
    assert Sensor.GYRO in quiet.sense_all()
    assert RobotAdapter.opt_in_sensors == frozenset({Sensor.CAMERA})
