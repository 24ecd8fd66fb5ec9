"""EPuckReal end to end against the protocol emulator, over loopback.

Each case runs the emulator (embedded simulator behind the protocol) in a thread and
drives it through the public factories, exactly as ``--backend epuck2-wifi`` /
``--backend sercom`` would. Faults are injected on the emulator's side of the line.
"""

from __future__ import annotations

import dataclasses
import socket
import threading
import time
from collections.abc import Callable
from contextlib import AbstractContextManager
from typing import Any

import pytest
from emulation_helpers import running_emulation

from puckboard.backends.epuck import EPuckReal, open_sercom, open_wifi
from puckboard.backends.epuck.emulator import pty_available
from puckboard.control.emulation import Emulation
from puckboard.errors import ConnectionLostError, NotSupportedError
from puckboard.records import Ground, Proximity, Sensor
from puckboard.scenario.scene import Noise
from puckboard.scenario.scenefile import load_scene

pytestmark = pytest.mark.network

# the shipped line-follow scene without noise or start jitter: exact expectations
SCENE = dataclasses.replace(load_scene("line-follow"), noise=Noise(0.0, 0.0, 0.0, 0.0))

# (protocol, serial carrier, sercom model)
CARRIERS = [
    pytest.param(("wifi", None, None), id="wifi"),
    pytest.param(("sercom", "tcp", "e-puck2"), id="sercom-e-puck2-socket"),
    pytest.param(("sercom", "tcp", "e-puck1"), id="sercom-e-puck1-socket"),
    pytest.param(
        ("sercom", "pty", "e-puck2"),
        id="sercom-e-puck2-pty",
        marks=pytest.mark.skipif(not pty_available(), reason="pseudo-terminals are POSIX-only"),
    ),
]


def emulated(protocol: str, serial: str | None) -> AbstractContextManager[Emulation]:
    return running_emulation(SCENE, protocol, serial, seed=3, seconds=60.0)


def connect(em: Emulation, model: str | None, **kw: Any) -> Any:
    if em.protocol == "wifi":
        return open_wifi(SCENE, **em.info.options, **kw)
    return open_sercom(SCENE, **em.info.options, model=model, **kw)


def eventually(cond: Callable[[], bool], within: float = 5.0) -> bool:
    """Serial actuator commands get no reply, so the robot applies them a moment later."""
    deadline = time.monotonic() + within
    while not cond():
        if time.monotonic() > deadline:
            return False
        time.sleep(0.01)
    return True


def finishes(fn: Callable[[], Any], within: float = 10.0) -> BaseException | None:
    """Run ``fn`` in a thread; fail the test if it hangs; return what it raised."""
    box: dict[str, BaseException | None] = {"exc": None}

    def target() -> None:
        try:
            fn()
        except BaseException as exc:
            box["exc"] = exc

    t = threading.Thread(target=target, daemon=True)
    t.start()
    t.join(within)
    assert not t.is_alive(), f"call still blocked after {within} s"
    return box["exc"]


@pytest.mark.parametrize("carrier", CARRIERS)
def test_connect_sense_drive_camera_close(carrier: tuple[str, str | None, str | None]) -> None:
    protocol, serial, model = carrier
    with emulated(protocol, serial) as em, connect(em, model) as conn:
        robot = conn.adapters["epuck"]
        assert isinstance(robot, EPuckReal)
        assert robot.backend_name == em.info.backend
        records = robot.sense_all()
        prox, ground = records[Sensor.PROXIMITY], records[Sensor.GROUND]
        assert isinstance(prox, Proximity) and isinstance(ground, Ground)
        assert ground.value[1] < 0.5 < ground.value[0]  # starts on the line, centre sensor dark
        assert (prox.distance == 0.05).all()  # nothing around on the line-follow floor
        # drive straight, then the counters and the dead-reckoned pose must have moved
        robot.set_wheel_speeds(4.0, 4.0)
        assert eventually(lambda: em.robot.speeds == (637, 637))  # 4 rad/s = 636.6 steps/s
        deadline = time.monotonic() + 5
        enc = robot.refresh(Sensor.ENCODERS)
        while enc.left < 0.5 and time.monotonic() < deadline:
            time.sleep(0.05)
            enc = robot.refresh(Sensor.ENCODERS)
        assert enc.left >= 0.5 and enc.right >= 0.5
        pose = robot.sense_all()[Sensor.POSE]
        assert pose.x > SCENE.robots[0].x + 0.005 and not pose.ground_truth
        image = robot.camera_image()
        expected = (120, 160, 3) if protocol == "wifi" else (40, 40, 3)
        assert image.pixels.shape == expected
        assert image.pixels.std() > 0  # a rendered floor, not a blank buffer
        with pytest.raises(NotSupportedError, match="cannot be stepped"):
            robot.step()
    assert robot.closed
    assert eventually(lambda: em.robot.speeds == (0, 0))  # close() zeroed the wheels


@pytest.mark.parametrize("carrier", CARRIERS)
def test_disconnect_mid_run_gives_a_clear_error(
    carrier: tuple[str, str | None, str | None],
) -> None:
    protocol, serial, model = carrier
    with emulated(protocol, serial) as em:
        conn = connect(em, model, timeout=0.3, retries=1)
        robot = conn.adapters["epuck"]
        robot.set_wheel_speeds(2.0, 2.0)
        em.server.drop_client()
        time.sleep(0.3)
        exc = finishes(lambda: [robot.sense_all() for _ in range(3)])
        assert isinstance(exc, ConnectionLostError), exc
        assert str(exc)  # says what was lost
        # once lost, every call fails at once instead of waiting again
        again = finishes(robot.sense_all, within=1.0)
        assert isinstance(again, ConnectionLostError)
        assert finishes(conn.close) is None  # closing a lost robot is quiet
        assert eventually(lambda: em.robot.speeds == (0, 0))  # the robot stops when the client goes


@pytest.mark.parametrize("carrier", CARRIERS)
def test_garbage_on_the_line_is_resynchronised(carrier: tuple[str, str | None, str | None]) -> None:
    protocol, serial, model = carrier
    with emulated(protocol, serial) as em, connect(em, model, timeout=0.3) as conn:
        robot = conn.adapters["epuck"]
        link = robot.link
        for garbage in (b"\x55\xaa\x13", b"\x02" + bytes(range(40)), b"\x01\x03\x00\xff" * 9):
            em.server.inject(garbage)
            records = robot.sense_all()
            ground = records[Sensor.GROUND]
            assert ground.value[1] < 0.5 < ground.value[0]  # still the true readings
            assert (records[Sensor.PROXIMITY].distance == 0.05).all()
        assert link.resyncs >= 1
        assert not link.broken


def test_silent_robot_times_out_with_a_clear_error() -> None:
    listener = socket.create_server(("127.0.0.1", 0))
    port = listener.getsockname()[1]
    accepted: list[socket.socket] = []
    threading.Thread(target=lambda: accepted.append(listener.accept()[0]), daemon=True).start()
    try:
        box: dict[str, Any] = {}
        exc = finishes(
            lambda: box.setdefault(
                "c", open_wifi(SCENE, host="127.0.0.1", port=port, timeout=0.2, retries=1)
            )
        )
        assert isinstance(exc, ConnectionLostError)
        assert "stopped answering" in str(exc) or "expected bytes" in str(exc)
    finally:
        for s in accepted:
            s.close()
        listener.close()


def test_watchdog_stops_wheels_when_commands_stop() -> None:
    with emulated("wifi", None) as em, connect(em, None, command_timeout=0.2) as conn:
        robot = conn.adapters["epuck"]
        robot.set_wheel_speeds(3.0, 3.0)
        assert eventually(lambda: em.robot.speeds != (0, 0))
        time.sleep(0.3)
        robot.sense_all()  # sensing goes on, commands do not: the watchdog stops the wheels
        assert eventually(lambda: em.robot.speeds == (0, 0))


def test_factory_errors_are_clear() -> None:
    with pytest.raises(ValueError, match="--host"):
        open_wifi(SCENE)
    with pytest.raises(ValueError, match="--device"):
        open_sercom(SCENE)
    with pytest.raises(ValueError, match="backend sercom"):
        open_wifi(SCENE, host="127.0.0.1", device="/dev/rfcomm0")
    with pytest.raises(ValueError, match="socket://"):
        open_sercom(SCENE, device="/dev/rfcomm0", host="127.0.0.1")
    with pytest.raises(TypeError, match="colour"):
        open_wifi(SCENE, host="127.0.0.1", colour="red")
    free = socket.create_server(("127.0.0.1", 0))
    port = free.getsockname()[1]
    free.close()  # nothing listens there now
    with pytest.raises(ConnectionLostError, match="selector is at 15"):
        open_wifi(SCENE, host="127.0.0.1", port=port, connect_timeout=1.0)


def test_registry_selects_the_real_backends() -> None:
    from puckboard.backends.registry import resolve_backend

    assert resolve_backend("epuck2-wifi") is open_wifi
    assert resolve_backend("sercom") is open_sercom


@pytest.mark.parametrize("carrier", CARRIERS)
def test_ir_calibration_request(carrier: tuple[str, str | None, str | None]) -> None:
    protocol, serial, model = carrier
    with emulated(protocol, serial) as em, connect(em, model) as conn:
        robot = conn.adapters["epuck"]
        if model == "e-puck1":
            with pytest.raises(NotSupportedError, match="e-puck1"):
                robot.calibrate_ir()
            return
        robot.calibrate_ir()
        assert eventually(lambda: em.robot.calibrations == 1)
        robot.sense_all()  # the flag was sent once: later exchanges do not recalibrate
        assert em.robot.calibrations == 1


def test_image_rotation_turns_sideways_cameras() -> None:
    import numpy as np

    with emulated("wifi", None) as em:
        with connect(em, None) as conn:
            upright = conn.adapters["epuck"].camera_image().pixels
        with connect(em, None, image_rotation=1) as conn:
            turned = conn.adapters["epuck"].camera_image().pixels
    assert turned.shape == (160, 120, 3)
    assert np.array_equal(turned, np.rot90(upright, 1))  # the robot stood still in between


@pytest.mark.parametrize("carrier", CARRIERS[:2])
def test_step_counters_wrap_on_the_wire_but_not_in_the_encoders(
    carrier: tuple[str, str | None, str | None],
) -> None:
    protocol, serial, model = carrier
    with emulated(protocol, serial) as em:
        em.robot.set_steps(32700, -32700)  # the counters are about to wrap
        with connect(em, model) as conn:
            robot = conn.adapters["epuck"]
            robot.set_wheel_speeds(4.0, -4.0)  # turn on the spot: left counts up, right down

            def wrapped() -> bool:
                robot.sense_all()
                left, right = robot.last_block.steps
                return left < 0 < right  # both int16 counters went round

            assert eventually(wrapped)
            enc = robot.refresh(Sensor.ENCODERS)
            assert 0 < enc.left < 10 and -10 < enc.right < 0  # rad: no 65536-step jump
            assert enc.left == pytest.approx(-enc.right, rel=0.2)
