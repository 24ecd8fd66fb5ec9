"""The adapter contract (on the shipped fake robot) and the control loop's shutdown paths."""

from __future__ import annotations

import logging
import threading
import time

import numpy as np
import pytest

from puckboard.backends import FakeAdapter, FakeClock, RobotAdapter
from puckboard.behaviours import Controller, Cruise, Layer, improved
from puckboard.blackboard import Blackboard
from puckboard.control import ControlLoop
from puckboard.errors import AdapterClosedError, NotSupportedError
from puckboard.records import Proximity, Sensor, WheelCommand


def test_sense_all_writes_every_enabled_sensor_atomically():
    fake = FakeAdapter("r0")
    fake.set_proximity(front_left=0.02)
    records = fake.sense_all()
    assert Sensor.CAMERA not in records
    assert isinstance(records[Sensor.PROXIMITY], Proximity)
    keys = fake.ns.keys()
    for s in (Sensor.PROXIMITY, Sensor.GROUND, Sensor.ENCODERS, Sensor.POSE):
        assert s.key in keys
    stamps = {fake.ns.get(s.key).stamp for s in records}
    assert len(stamps) == 1  # one time frame
    assert fake.ns.value("proximity").front_left == pytest.approx(0.02)


def test_refresh_reads_one_sensor():
    fake = FakeAdapter()
    fake.set_ground(centre=0.1)
    g = fake.refresh("ground")
    assert g.centre == pytest.approx(0.1)
    assert fake.ns.keys() == ["ground"]
    with pytest.raises(ValueError, match="unknown sensor 'sonar'"):
        fake.refresh("sonar")


def test_wheel_commands_are_clamped_with_one_warning(caplog):
    fake = FakeAdapter()
    limit = fake.profile.max_wheel_speed
    with caplog.at_level(logging.WARNING):
        sent = fake.set_wheel_speeds(100.0, -100.0)
        fake.set_wheel_speeds(100.0, 0.0)
    assert sent == WheelCommand(limit, -limit)
    assert caplog.text.count("exceeds") == 1


def test_a_command_of_integers_is_sent_as_floats():
    fake = FakeAdapter()
    sent = fake.command_wheels(WheelCommand(1, -2))  # a layer may build one of ints
    assert sent == WheelCommand(1.0, -2.0)
    assert [type(v) for v in fake.commands[-1][1:]] == [float, float]


def test_the_loop_sets_how_old_a_sensor_record_may_be():
    clock = FakeClock(dt=0.05)
    robot = FakeAdapter(clock=clock)
    robot.sense_all()
    clock.step(4)  # 0.2 s later
    assert robot.ns.snapshot().status(Sensor.PROXIMITY.key) == "fresh"  # no limit yet
    ControlLoop([(robot, improved())], stale_after=0.1)
    assert robot.ns.snapshot().status(Sensor.PROXIMITY.key) == "stale"
    assert robot.ns.snapshot().status(Sensor.CAMERA.key) == "missing"
    with pytest.raises(ValueError, match="Proximity"):  # the schema is still declared
        robot.ns.put(Sensor.PROXIMITY.key, np.zeros(8))


def test_stepping_advances_the_shared_clock_and_moves_the_robot():
    clock = FakeClock(dt=0.05)
    a = FakeAdapter("a", clock=clock)
    b = FakeAdapter("b", clock=clock, blackboard=a.blackboard)
    a.set_wheel_speeds(2.0, 2.0)
    a.step(20)
    assert clock.time == pytest.approx(1.0)
    assert a.x == pytest.approx(2.0 * a.profile.wheel_radius * 1.0)
    assert b.x == 0.0


class RealTimeFake(FakeAdapter):
    """A fake without a stepper, standing in for a real robot."""

    def __init__(self, **kw):
        kw.setdefault("blackboard", Blackboard())  # host monotonic clock
        super().__init__(**kw)
        self.stepper = None


def test_real_robot_cannot_step_and_says_why():
    robot = RealTimeFake()
    with pytest.raises(NotSupportedError, match="cannot be stepped"):
        robot.step()


def test_closed_adapter_refuses_use_and_zeroes_wheels():
    fake = FakeAdapter()
    fake.set_wheel_speeds(1.0, 1.0)
    fake.close()
    assert fake.wheels == (0.0, 0.0)
    with pytest.raises(AdapterClosedError):
        fake.sense_all()
    fake.close()  # idempotent


class OverlapDetector(RobotAdapter):
    """Records whether two transport calls were ever inside the hooks at the same time."""

    backend_name = "overlap"

    def __init__(self):
        self.inside = 0
        self.max_inside = 0
        self.calls = 0
        self.guard = threading.Lock()
        super().__init__("o")

    def _enter(self):
        with self.guard:
            self.inside += 1
            self.max_inside = max(self.max_inside, self.inside)
            self.calls += 1
        time.sleep(0.0005)
        with self.guard:
            self.inside -= 1

    def _read_sensors(self, sensors):
        self._enter()
        return {Sensor.PROXIMITY: Proximity.nothing()}

    def _write_wheels(self, left, right):
        self._enter()

    def _read_camera(self):
        from puckboard.records import CameraImage

        self._enter()
        return CameraImage(np.zeros((2, 2, 3), dtype=np.uint8))


def test_transport_calls_never_overlap_with_sensing_and_camera_threads():
    robot = OverlapDetector()
    robot.enable(Sensor.CAMERA)
    robot.start_sensing_thread(0.001)
    robot.start_camera_thread(0.001)
    deadline = time.monotonic() + 0.5
    while time.monotonic() < deadline:
        robot.set_wheel_speeds(0.1, 0.1)
    robot.close()
    assert robot.calls > 50
    assert robot.max_inside == 1


def test_observers_learn_what_changed_and_receive_images():
    fake = FakeAdapter()
    changed, images = [], []
    fake.add_sensor_observer(lambda a, c: changed.append(c))
    fake.add_camera_observer(lambda a, img: images.append(img.pixels.shape))
    fake.refresh(Sensor.GROUND)
    fake.camera_image()
    assert changed == [frozenset({Sensor.GROUND})]
    assert images == [(39, 52, 3)]


def test_sensing_thread_keeps_the_blackboard_fresh():
    fake = RealTimeFake()
    fake.start_sensing_thread(0.01)
    first = fake.ns.wait_for("proximity", timeout=2)
    later = fake.ns.wait_for("proximity", after_seq=first.seq + 2, timeout=2)
    fake.close()
    assert later.seq >= first.seq + 3


def test_watchdog_stops_wheels_when_commands_go_stale():
    fake = RealTimeFake(command_timeout=0.05)
    fake.set_wheel_speeds(1.0, 1.0)
    time.sleep(0.1)
    fake.sense_all()
    assert fake.wheels == (0.0, 0.0)


class Boom(Layer):
    def __init__(self, after):
        super().__init__("Boom")
        self.after = after
        self.ticks = 0

    def command(self, frame):
        self.ticks += 1
        if self.ticks > self.after:
            raise RuntimeError("layer failed")
        return WheelCommand(1.0, 1.0)


def test_exception_in_a_layer_zeroes_wheels_and_closes_adapters():
    clock = FakeClock()
    bb = Blackboard(clock=lambda: clock.time)
    robots = [FakeAdapter(f"r{i}", clock=clock, blackboard=bb) for i in range(2)]
    closed = []
    loop = ControlLoop([(robots[0], Controller([Boom(after=3)])), (robots[1], improved())])
    loop.add_close_observer(lambda lp: closed.append(lp.cycles))
    with pytest.raises(RuntimeError, match="layer failed"):
        loop.run(duration=10)
    for r in robots:
        assert r.closed
        assert r.wheels == (0.0, 0.0)
    assert closed == [3]


def test_ctrl_c_zeroes_wheels_and_closes_adapters():
    clock = FakeClock()
    robot = FakeAdapter(clock=clock)

    def interrupt(loop):
        if loop.cycles == 5:
            raise KeyboardInterrupt

    loop = ControlLoop([(robot, improved())])
    loop.add_observer(interrupt)
    with pytest.raises(KeyboardInterrupt):
        loop.run(duration=10)
    assert robot.closed
    assert robot.commands[-1][1:] == (0.0, 0.0)


def test_synchronous_loop_steps_shared_world_once_per_cycle():
    clock = FakeClock(dt=0.05)
    bb = Blackboard(clock=lambda: clock.time)
    robots = [FakeAdapter(f"r{i}", clock=clock, blackboard=bb) for i in range(3)]
    loop = ControlLoop([(r, Controller([Cruise(1.0)])) for r in robots], period=0.1)
    n = loop.run(duration=1.0)
    assert n == 10
    assert clock.time == pytest.approx(1.0)
    for r in robots:
        assert r.x == pytest.approx(1.0 * r.profile.wheel_radius * 1.0, rel=0.06)
        assert r.ns.value("command/layer") == "Cruise"


def test_loop_rejects_bad_periods_and_mixed_backends():
    clock = FakeClock(dt=0.05)
    robot = FakeAdapter(clock=clock)
    with pytest.raises(ValueError, match="whole number of simulation steps"):
        ControlLoop([(robot, improved())], period=0.07)
    with pytest.raises(ValueError, match="cannot mix"):
        ControlLoop([(robot, improved()), (RealTimeFake(), improved())])
    with pytest.raises(ValueError, match="needs a duration"):
        ControlLoop([(robot, improved())]).run()


def test_wall_clock_loop_keeps_its_period():
    robot = RealTimeFake()
    loop = ControlLoop([(robot, improved())], period=0.02)
    start = time.monotonic()
    loop.run(cycles=5)
    assert time.monotonic() - start >= 5 * 0.02 * 0.9
    assert robot.closed


def test_wheels_stopped_says_whether_a_stop_reached_the_robot():
    """After a lost connection the command line says whether the robots may still be
    driving: only a stop that was sent without an error counts."""
    from puckboard.errors import ConnectionLostError

    class Unplugged(FakeAdapter):
        lost = False

        def _write_wheels(self, left, right):
            if self.lost:
                raise ConnectionLostError("unplugged")
            super()._write_wheels(left, right)

    robot = Unplugged()
    assert robot.wheels_stopped  # nothing commanded yet
    robot.set_wheel_speeds(2.0, 2.0)
    assert not robot.wheels_stopped
    robot.lost = True
    with pytest.raises(ConnectionLostError):
        robot.stop_wheels()
    robot.close()  # its last try to zero the wheels fails too
    assert not robot.wheels_stopped

    robot = Unplugged()
    robot.set_wheel_speeds(2.0, 2.0)
    robot.close()  # zeroes the wheels on the way out
    assert robot.wheels_stopped
