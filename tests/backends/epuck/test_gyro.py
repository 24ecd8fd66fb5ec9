"""The e-puck2 gyro on the wire: units, codecs, and EPuckReal reading the emulator."""

from __future__ import annotations

import dataclasses
import math
import struct
import time
from contextlib import AbstractContextManager

import pytest
from emulation_helpers import running_emulation
from hypothesis import given
from hypothesis import strategies as st

from puckboard.backends.epuck import open_sercom, open_wifi
from puckboard.backends.epuck import sercom_codec as sc
from puckboard.backends.epuck.blocks import SensorBlock
from puckboard.backends.epuck.emulator import EmulatedRobot
from puckboard.backends.epuck.units import (
    GYRO_COUNTS_PER_DPS,
    angular_velocity_from_raw,
    angular_velocity_to_raw,
)
from puckboard.control.emulation import Emulation
from puckboard.errors import NotSupportedError
from puckboard.records import AngularVelocity, Sensor
from puckboard.scenario.scene import Noise
from puckboard.scenario.scenefile import load_scene
from puckboard.sim.world import World

SCENE = dataclasses.replace(load_scene("line-follow"), noise=Noise())
RAD_PER_COUNT = math.radians(1.0) / GYRO_COUNTS_PER_DPS
FULL_SCALE = math.radians(250.0)  # rad/s

rates = st.floats(-FULL_SCALE, FULL_SCALE, allow_nan=False)


def test_131_counts_are_one_degree_per_second_and_ccw_is_positive_z() -> None:
    assert angular_velocity_from_raw((0, 0, 131)) == pytest.approx((0.0, 0.0, math.radians(1.0)))
    # the chip's -y points forward and its x to the left (inferred axis mapping)
    assert angular_velocity_from_raw((0, -131, 0)) == pytest.approx((math.radians(1.0), 0, 0))
    assert angular_velocity_from_raw((131, 0, 0)) == pytest.approx((0, math.radians(1.0), 0))
    assert angular_velocity_to_raw((0.0, 0.0, -math.radians(90.0))) == (0, 0, -11790)


@given(rates, rates, rates)
def test_gyro_units_round_trip_within_one_count(x: float, y: float, z: float) -> None:
    raw = angular_velocity_to_raw((x, y, z))
    back = angular_velocity_from_raw(raw)
    assert back == pytest.approx((x, y, z), abs=0.5 * RAD_PER_COUNT + 1e-12)


def test_gyro_saturates_at_the_full_scale() -> None:
    assert angular_velocity_to_raw((0.0, 0.0, 100.0))[2] == 32767
    assert angular_velocity_to_raw((0.0, 0.0, -100.0))[2] == -32768
    with pytest.raises(ValueError, match="int16"):
        angular_velocity_to_raw((0.0, 0.0, math.nan))


@pytest.mark.parametrize("wifi", [True, False])
def test_gyro_sits_in_bytes_18_to_23_of_the_sensor_block(wifi: bool) -> None:
    data = SensorBlock(gyro=(1, -2, 30000)).encode(wifi=wifi)
    assert data[18:24] == struct.pack("<3h", 1, -2, 30000)
    assert SensorBlock.decode(data).gyro == (1, -2, 30000)


def test_sercom_gyro_command() -> None:
    assert sc.encode_request([(sc.GET_GYRO, b"")]) == bytes.fromhex("9900")  # [-'g'][0]
    assert sc.reply_size(sc.GET_GYRO) == 6


def test_emulated_robot_encodes_the_simulated_yaw_rate() -> None:
    world = World(SCENE)
    robot = EmulatedRobot(world, 0)
    world.set_wheel_speeds(0, -2.0, 2.0)
    world.step()
    raw = robot.gyro()
    assert raw == robot.sensor_block().gyro
    z = angular_velocity_from_raw(raw)[2]
    assert z == pytest.approx(float(world.angular_velocities[0, 2]), abs=RAD_PER_COUNT)
    assert z > 0.5


def _emulated(protocol: str, serial: str | None) -> AbstractContextManager[Emulation]:
    return running_emulation(SCENE, protocol, serial, seed=1, seconds=30.0)


@pytest.mark.network
@pytest.mark.parametrize(
    ("protocol", "serial", "model"),
    [("wifi", None, None), ("sercom", "tcp", "e-puck2")],
    ids=["wifi", "sercom-e-puck2"],
)
def test_epuck_real_reads_the_emulated_yaw_rate(
    protocol: str, serial: str | None, model: str | None
) -> None:
    with _emulated(protocol, serial) as em:
        opener = open_wifi if protocol == "wifi" else open_sercom
        options = {} if model is None else {"model": model}
        with opener(SCENE, **em.info.options, **options) as conn:
            robot = conn.adapters["epuck"]
            assert Sensor.GYRO in robot.enabled_sensors  # a real e-puck2 reads it every cycle
            robot.set_wheel_speeds(-3.0, 3.0)
            deadline = time.monotonic() + 5.0
            gyro = robot.sense_all()[Sensor.GYRO]
            while gyro.z < 0.1 and time.monotonic() < deadline:
                time.sleep(0.02)
                gyro = robot.sense_all()[Sensor.GYRO]
            assert isinstance(gyro, AngularVelocity)
            # what the emulated robot turns at: the command in whole motor steps per second
            steps = em.robot.speeds
            p = robot.profile
            expected = p.body_velocity(p.steps_to_rad(steps[0]), p.steps_to_rad(steps[1]))[1]
            assert gyro.z == pytest.approx(expected, abs=RAD_PER_COUNT)
            assert robot.ns.value("gyro") is gyro


@pytest.mark.network
def test_an_epuck1_has_no_gyro() -> None:
    with (
        _emulated("sercom", "tcp") as em,
        open_sercom(SCENE, **em.info.options, model="e-puck1") as conn,
    ):
        robot = conn.adapters["epuck"]
        assert Sensor.GYRO not in robot.available_sensors
        assert Sensor.GYRO not in robot.sense_all()
        with pytest.raises(NotSupportedError, match="no gyro"):
            robot.enable("gyro")
