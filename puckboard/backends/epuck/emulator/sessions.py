"""The robot's side of each protocol: bytes in, bytes out, no I/O.

A session turns what a client sends into what the e-puck would answer, acting on an
:class:`~puckboard.backends.epuck.emulator.robot.EmulatedRobot`. The servers in
:mod:`puckboard.backends.epuck.emulator.servers` only move bytes; keeping the protocol here makes it
testable without sockets and shared by TCP and the pseudo-terminal.
"""

from __future__ import annotations

import logging
from typing import Protocol

from .. import sercom_codec as sc
from ..blocks import ActuatorBlock
from ..sercom_codec import RequestParser
from ..wifi_codec import (
    EMPTY_PACKET,
    IMAGE_HEIGHT,
    IMAGE_WIDTH,
    CommandFramer,
    encode_image_packet,
    encode_sensor_packet,
)
from .robot import EmulatedRobot

__all__ = ["SercomSession", "Session", "WifiSession"]

log = logging.getLogger(__name__)


class Session(Protocol):
    def feed(self, data: bytes) -> bytes: ...


class WifiSession:
    """e-puck2 Wi-Fi: each 0x80 command is applied and answered with the packets it asks
    for (sensors 0x02, image 0x01) or the empty packet 0x03. Bytes that start no command
    are skipped, as the robot's radio module does."""

    def __init__(self, robot: EmulatedRobot) -> None:
        self.robot = robot
        self.framer = CommandFramer()

    def feed(self, data: bytes) -> bytes:
        self.framer.feed(data)
        out = bytearray()
        for cmd in self.framer.commands():
            self.robot.count_command()
            self.robot.apply(cmd.actuators)
            if cmd.sensors:
                out += encode_sensor_packet(self.robot.sensor_block())
            if cmd.image:
                out += encode_image_packet(self.robot.camera(IMAGE_WIDTH, IMAGE_HEIGHT))
            if not (cmd.sensors or cmd.image):
                out += EMPTY_PACKET
        if self.framer.skipped:
            log.info("Wi-Fi emulator skipped %d stray bytes", self.framer.skipped)
            self.framer.skipped = 0
        return bytes(out)


class SercomSession:
    """Advanced sercom: binary requests (e-puck2 0x08/0x09 and the classic single-letter
    commands) and a few ASCII commands (``V``, ``S``, ``D,l,r``, ``E``, ``N``, ``Q``)."""

    def __init__(self, robot: EmulatedRobot, *, camera_size: tuple[int, int] = (40, 40)) -> None:
        self.robot = robot
        self.camera_size = camera_size
        self.parser = RequestParser()

    def feed(self, data: bytes) -> bytes:
        out = bytearray()
        for kind, payload in self.parser.feed(data):
            self.robot.count_command()
            if kind == "binary":
                assert isinstance(payload, list)
                out += self._binary(payload)
            else:
                assert isinstance(payload, str)
                out += self._ascii(payload).encode("ascii") + b"\r\n"
        return bytes(out)

    def _binary(self, items: list[tuple[int, bytes]]) -> bytes:
        r = self.robot
        out = bytearray()
        for cmd, params in items:
            if cmd == sc.ALL_ACTUATORS:
                r.apply(ActuatorBlock.decode(params))
            elif cmd == sc.SET_SPEED:
                left, right = sc.decode_int16s(params, 2)
                r.set_speeds(left, right)
            elif cmd == sc.SET_STEPS:
                left, right = sc.decode_int16s(params, 2)
                r.set_steps(left, right)
            elif cmd == sc.ALL_SENSORS:
                out += r.sensor_block().encode(wifi=False)
            elif cmd == sc.GET_PROXIMITY:
                out += sc.encode_int16s(r.proximity())
            elif cmd == sc.GET_AMBIENT:
                out += sc.encode_int16s(r.sensor_block().ambient)
            elif cmd == sc.GET_GROUND:
                out += sc.encode_int16s(r.ground())
            elif cmd == sc.GET_STEPS:
                out += sc.encode_int16s(r.steps())
            elif cmd == sc.GET_SPEED:
                out += sc.encode_int16s(r.speeds)
            elif cmd == sc.GET_ACCELEROMETER:
                out += sc.encode_int16s(r.accelerometer())
            elif cmd == sc.GET_GYRO:
                out += sc.encode_int16s(r.gyro())
            elif cmd == sc.GET_IMAGE:
                w, h = self.camera_size
                out += sc.encode_camera(r.camera(w, h))
            elif cmd in sc.PARAMETER_SIZES:
                pass  # LEDs, RGB, sensor modes: accepted, nothing to emulate
            else:
                log.debug("sercom emulator ignores binary command 0x%02x", cmd)
        return bytes(out)

    def _ascii(self, line: str) -> str:
        r = self.robot
        parts = line.split(",")
        cmd = parts[0].strip()
        key = cmd.upper() if cmd not in ("b", "g") else cmd
        try:
            if key == "V":
                return "v,Version 2 (puckboard emulator)"
            if key == "S":
                r.stop()
                return "s"
            if key == "K":
                r.calibrate_ir()
                return "k, Calibration finished"
            if key == "D":
                left, right = int(parts[1]), int(parts[2])
                r.set_speeds(left, right)
                return "d"
            if key == "E":
                return "e,{},{}".format(*r.speeds)
            if key == "Q":
                return "q,{},{}".format(*r.steps())
            if key == "N":
                return "n," + ",".join(str(v) for v in r.proximity())
            if key == "M":
                return "m," + ",".join(str(v) for v in r.ground())
        except (IndexError, ValueError):
            return f"z,bad parameters for {cmd}"
        return "z,Command not found"
