"""The emulator on its own: the robot side of the protocols and the scene's other robots."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest

from puckboard.backends.embedded import EmbeddedAdapter
from puckboard.backends.epuck import EPuckReal, open_wifi
from puckboard.backends.epuck.blocks import ActuatorBlock, SensorBlock
from puckboard.backends.epuck.emulator import EmulatedRobot, WifiSession
from puckboard.backends.epuck.link import Reply
from puckboard.backends.epuck.units import distance_from_calibrated
from puckboard.backends.epuck.wifi_codec import WifiCommand
from puckboard.control.emulation import Emulation
from puckboard.records import Sensor
from puckboard.scenario.scenefile import load_scene
from puckboard.sim.world import World


def test_wifi_session_answers_like_the_robot() -> None:
    robot = EmulatedRobot(World(load_scene("line-follow")), 0)
    session = WifiSession(robot)
    assert session.feed(WifiCommand().encode()) == b"\x03"  # nothing asked: the empty packet
    reply = session.feed(
        b"\x17\x42" + WifiCommand(ActuatorBlock(left=300, right=-300), sensors=True).encode()
    )
    assert reply[0] == 0x02 and len(reply) == 105  # stray bytes skipped, then 0x02 + 104
    assert robot.speeds == (300, -300)
    block = SensorBlock.decode(reply[1:])
    assert block.selector == 15
    assert block.ground[1] < 512 < block.ground[0]  # starts on the line
    both = session.feed(WifiCommand(image=True, sensors=True).encode())
    assert len(both) == (1 + 104) + (1 + 38400)


def test_emulated_speeds_are_clamped_like_the_firmware() -> None:
    robot = EmulatedRobot(World(load_scene("line-follow")), 0)
    robot.set_speeds(5000, -5000)
    assert robot.speeds == (1100, -1100)


def test_calibration_next_to_an_obstacle_blinds_the_sensors() -> None:
    world = World(load_scene("arena"))
    robot = EmulatedRobot(world, 0)
    # put the robot right in front of the arena's wall, facing it
    arena = world.scene.arena
    assert arena is not None
    world.set_pose(0, arena.xmax - 0.05, (arena.ymin + arena.ymax) / 2, 0.0)
    seen = distance_from_calibrated(robot.proximity(), robot.profile)
    assert seen[0] < 0.05 and seen[7] < 0.05  # the front sensors see the wall
    robot.calibrate_ir()
    blind = distance_from_calibrated(robot.proximity(), robot.profile)
    assert blind[0] == 0.05 and blind[7] == 0.05  # after calibrating there, they do not


def test_the_other_robots_drive_with_their_own_controllers() -> None:
    scene = load_scene("two-robot-pass")
    assert len(scene.robots) == 2
    em = Emulation(scene, protocol="wifi")
    start = np.array(em.world.poses[1])
    thread = threading.Thread(target=em.run, args=(1.0,), daemon=True)
    thread.start()
    try:
        with open_wifi(scene, **em.info.options) as conn:
            robot = conn.adapters[scene.robots[0].name]
            robot.sense_all()  # the first command starts the clock
            thread.join(10)
    finally:
        em.stop()
        thread.join(5)
    moved = float(np.hypot(*(em.world.poses[1, :2] - start[:2])))
    assert moved > 0.01  # about 4 cm in 1 s at the controllers' cruising speed
    still = Emulation(scene, protocol="wifi", others="still")
    try:
        assert still._others == []
    finally:
        still.close()


def test_emulation_rejects_bad_arguments() -> None:
    with pytest.raises(ValueError, match="protocol"):
        Emulation("line-follow", protocol="usb")
    with pytest.raises(ValueError, match="others"):
        Emulation("line-follow", others="ghosts")


def test_run_without_a_client_returns_after_the_wait() -> None:
    em = Emulation("line-follow", protocol="wifi")
    t0 = time.monotonic()
    result = em.run(5.0, wait_for_client=0.2)
    assert time.monotonic() - t0 < 5.0
    assert result.steps == 0  # the clock never started


def _drive_briefly(em: Emulation, then: str) -> threading.Thread:
    thread = threading.Thread(target=em.run, args=(30.0,), daemon=True)
    thread.start()
    conn = open_wifi(em.scene, **em.info.options)
    robot = conn.adapters[em.robot.name]
    robot.set_wheel_speeds(1.0, 1.0)
    if then == "disconnect":
        conn.close()
    return thread


def test_run_ends_when_the_tcp_client_leaves() -> None:
    em = Emulation("line-follow", protocol="wifi", idle_timeout=None)
    thread = _drive_briefly(em, "disconnect")
    thread.join(10)
    assert not thread.is_alive()
    assert em.ended_by == "client left"


def test_run_ends_when_the_client_falls_silent() -> None:
    em = Emulation("line-follow", protocol="wifi", idle_timeout=0.3, until_client_leaves=False)
    thread = _drive_briefly(em, "stay")
    thread.join(10)
    assert not thread.is_alive()
    assert em.ended_by.startswith("client silent")


def test_calibrated_proximity_never_goes_below_zero_on_the_wire() -> None:
    """As the firmware's get_calibrated_prox: a reading under its calibration offset is 0.

    After calibrating with a wall in front and backing away, the front sensors read less
    than their offset; the bytes of both protocols must then say 0, never a negative int16
    (which a client reading the field as unsigned sees as 65535, an obstacle touching).
    """
    from puckboard.backends.epuck import sercom_codec as sc
    from puckboard.backends.epuck.emulator import SercomSession

    world = World(load_scene("arena"))
    robot = EmulatedRobot(world, 0)
    arena = world.scene.arena
    assert arena is not None
    middle = (arena.ymin + arena.ymax) / 2
    world.set_pose(0, arena.xmax - 0.05, middle, 0.0)
    robot.calibrate_ir()
    world.set_pose(0, (arena.xmin + arena.xmax) / 2, middle, 0.0)
    wifi = WifiSession(robot)
    sercom = SercomSession(robot)
    for _ in range(20):  # the emulated noise differs each read
        packet = wifi.feed(WifiCommand(sensors=True).encode())
        assert packet[0] == 0x02
        ir_bytes = packet[1 + 37 : 1 + 53]  # bytes 37-52 of the block: 8 × int16 LE
        values = [int.from_bytes(ir_bytes[k : k + 2], "little") for k in range(0, 16, 2)]
        assert all(v <= 4095 for v in values), values
        reply = sercom.feed(sc.encode_request([(sc.GET_PROXIMITY, b"")]))
        assert len(reply) == 16
        unsigned = [int.from_bytes(reply[k : k + 2], "little") for k in range(0, 16, 2)]
        assert all(v <= 4095 for v in unsigned), unsigned
        assert unsigned[0] == 0 and unsigned[7] == 0  # calibrated at the wall: now below offset


class _SessionLink:
    """EPuckReal's link to an emulated robot in this process: every exchange goes through
    the Wi-Fi protocol's bytes, as over a socket."""

    backend_name = "epuck2-wifi"
    description = "an in-process Wi-Fi session"
    acc_scale = (768.0, 0.0)
    has_gyro = True

    def __init__(self, robot: EmulatedRobot) -> None:
        self.session = WifiSession(robot)

    def exchange(self, actuators: ActuatorBlock, *, sensors: bool, image: bool) -> Reply:
        reply = self.session.feed(WifiCommand(actuators, sensors=sensors).encode())
        return Reply(sensors=SensorBlock.decode(reply[1:]) if sensors else None)

    def close(self) -> None:
        pass


@pytest.mark.parametrize("gap", [0.004, 0.015, 0.03, 0.046, 0.06])
def test_embedded_and_emulated_robots_convert_the_same_values_to_the_same_distances(gap):
    """One simulated robot read two ways: by the embedded adapter (the world's calibrated
    values as floats) and by EPuckReal over the emulator's protocol (the same values
    rounded to the integers the robot sends). Both convert through the one function."""
    world = World(load_scene("arena"))
    arena = world.scene.arena
    assert arena is not None
    # facing the arena's east wall, ``gap`` from the front sensors' mid-point
    front = world.profiles[0].prox_poses[0].x
    world.set_pose(0, arena.xmax - front - gap, (arena.ymin + arena.ymax) / 2, 0.0)
    emulated = EmulatedRobot(world, 0)
    real = EPuckReal(_SessionLink(emulated), profile=emulated.profile, command_timeout=None)
    embedded = EmbeddedAdapter(world, 0)
    via_wire = real.sense_all()[Sensor.PROXIMITY]
    in_process = embedded.sense_all()[Sensor.PROXIMITY]
    profile = world.profiles[0]
    assert real.profile == embedded.profile == profile
    # the integers on the wire are the world's values, rounded
    assert via_wire.raw.tolist() == np.rint(in_process.raw).tolist()
    # each side's distances are its values through the one conversion
    assert via_wire.distance.tolist() == distance_from_calibrated(via_wire.raw, profile).tolist()
    assert in_process.distance.tolist() == world.prox_distance[0].tolist()
    assert (
        in_process.distance.tolist() == distance_from_calibrated(in_process.raw, profile).tolist()
    )
    # so the same values give the same distances, and rounding moves them a hair at most
    same = distance_from_calibrated(np.rint(in_process.raw), profile)
    assert same.tolist() == via_wire.distance.tolist()
    seen = in_process.distance < profile.prox_range
    assert seen.tolist() == (via_wire.distance < profile.prox_range).tolist()
    assert np.abs(via_wire.distance - in_process.distance).max() < 0.0005
    assert seen[0] == (gap < profile.prox_max_distance)
