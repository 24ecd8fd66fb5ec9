"""Advanced sercom, binary mode, as bytes (pure: no serial port here).

Over Bluetooth (e-puck1; e-puck2 with selector 3) and USB (e-puck2, selector 8) the
robot runs GCtronic's "advanced sercom" protocol. A first byte that is negative as an
int8 selects binary mode: the PC sends a sequence of *negated* command characters, each
followed by its parameters, and ends the sequence with a zero byte; the robot then
answers once with the concatenated replies, in order, every integer int16 little-endian.
For example ``[-'N'][-'Q'][0]`` = ``b2 af 00`` asks for the proximity sensors and the
step counters and gets 16 + 4 bytes back.

Commands used here (wire byte = ``-c & 0xff``):

==========  =====  ====================  =====================================
command     byte   parameters            reply
==========  =====  ====================  =====================================
``-'D'``    0xBC   int16 left, right     — (set speeds, steps/s)
``-'P'``    0xB0   int16 left, right     — (set step counters)
``-'L'``    0xB4   u8 led, u8 state      —
``-'N'``    0xB2   —                     8 × int16 calibrated proximity
``-'O'``    0xB1   —                     8 × int16 ambient light
``-'M'``    0xB3   —                     3 × int16 ground (more with cliff sensors)
``-'Q'``    0xAF   —                     2 × int16 step counters
``-'E'``    0xBB   —                     2 × int16 speeds
``-'a'``    0x9F   —                     3 × int16 accelerometer
``-'g'``    0x99   —                     3 × int16 gyro (e-puck2; 131 counts per °/s)
``-'I'``    0xB7   —                     mode, width, height, then the pixels
``-0x08``   0xF8   —                     e-puck2: all sensors, 103 bytes
``-0x09``   0xF7   19-byte actuator blk  e-puck2: set all actuators
==========  =====  ====================  =====================================

Sources: GCtronic wiki "Advanced sercom protocol"; e-puck2_main-processor
``src/epuck1x/Asercom2.c``; e-puck-library ``program/DemoGCtronic-complete/Asercom.c``.
"""

from __future__ import annotations

import struct
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from .blocks import ACTUATOR_BLOCK_SIZE, SENSOR_BLOCK_SERIAL_SIZE
from .units import rgb565_decode, rgb565_encode

__all__ = [
    "ALL_ACTUATORS",
    "ALL_SENSORS",
    "CAMERA_GREY",
    "CAMERA_RGB565",
    "PARAMETER_SIZES",
    "TERMINATOR",
    "RequestParser",
    "binary",
    "decode_camera",
    "decode_int16s",
    "encode_camera",
    "encode_int16s",
    "encode_request",
    "reply_size",
]

TERMINATOR = 0x00


def binary(command: str | int) -> int:
    """The wire byte of a binary command: the negated character (``-'N'`` → 0xB2)."""
    code = ord(command) if isinstance(command, str) else int(command)
    if not 0 < code < 0x80:
        raise ValueError(f"sercom commands are 1..127, got {command!r}")
    return (-code) & 0xFF


SET_SPEED = binary("D")
SET_STEPS = binary("P")
SET_LED = binary("L")
GET_PROXIMITY = binary("N")
GET_AMBIENT = binary("O")
GET_GROUND = binary("M")
GET_STEPS = binary("Q")
GET_SPEED = binary("E")
GET_ACCELEROMETER = binary("a")
GET_GYRO = binary("g")
GET_IMAGE = binary("I")
ALL_SENSORS = binary(0x08)
ALL_ACTUATORS = binary(0x09)

CAMERA_GREY = 0
CAMERA_RGB565 = 1

PARAMETER_SIZES: dict[int, int] = {
    SET_SPEED: 4,
    SET_STEPS: 4,
    SET_LED: 2,
    ALL_ACTUATORS: ACTUATOR_BLOCK_SIZE,
    binary(0x0A): 12,  # RGB LEDs
    binary(0x0F): 1,  # magnetometer enable
    binary(0x10): 1,  # proximity mode
    binary(0x11): 1,  # ToF enable
}
"""Bytes of inline parameters that follow each binary command (0 if absent)."""


def reply_size(command: int, *, prox_count: int = 8, ground_count: int = 3) -> int | None:
    """Reply length of a binary command, ``None`` for the camera (size in its header).

    ``prox_count``/``ground_count`` allow for firmware variants (10 proximity values on
    some e-puck1 builds, 4-5 ground values with cliff sensors).
    """
    sizes = {
        GET_PROXIMITY: 2 * prox_count,
        GET_AMBIENT: 2 * prox_count,
        GET_GROUND: 2 * ground_count,
        GET_STEPS: 4,
        GET_SPEED: 4,
        GET_ACCELEROMETER: 6,
        GET_GYRO: 6,
        ALL_SENSORS: SENSOR_BLOCK_SERIAL_SIZE,
    }
    if command == GET_IMAGE:
        return None
    if command in sizes:
        return sizes[command]
    if command in PARAMETER_SIZES:
        return 0
    raise ValueError(f"unknown binary sercom command 0x{command:02x}")


def encode_int16s(values: Iterable[int]) -> bytes:
    vals = [int(v) for v in values]
    return struct.pack(f"<{len(vals)}h", *vals)


def decode_int16s(
    data: bytes | bytearray | memoryview, count: int | None = None
) -> tuple[int, ...]:
    n = len(data) // 2 if count is None else count
    if len(data) != 2 * n:
        raise ValueError(f"expected {n} int16 values ({2 * n} bytes), got {len(data)} bytes")
    return struct.unpack(f"<{n}h", bytes(data))


def encode_request(items: Sequence[tuple[int, bytes]]) -> bytes:
    """One binary request: each ``(command byte, parameters)`` in turn, then the 0 byte."""
    out = bytearray()
    for cmd, params in items:
        expected = PARAMETER_SIZES.get(cmd, 0)
        if len(params) != expected:
            raise ValueError(
                f"command 0x{cmd:02x} takes {expected} parameter bytes, got {len(params)}"
            )
        if cmd < 0x80:
            raise ValueError(f"binary commands have the high bit set, got 0x{cmd:02x}")
        out.append(cmd)
        out += params
    out.append(TERMINATOR)
    return bytes(out)


def encode_camera(pixels: npt.NDArray[np.uint8], mode: int = CAMERA_RGB565) -> bytes:
    """The -'I' reply: mode, width, height, then RGB565 (or grey) pixels."""
    h, w = pixels.shape[:2]
    if not (0 < w < 256 and 0 < h < 256):
        raise ValueError(f"sercom images are at most 255×255, got {w}×{h}")
    if mode == CAMERA_RGB565:
        body = rgb565_encode(pixels)
    elif mode == CAMERA_GREY:
        body = np.asarray(pixels, dtype=np.float64).mean(axis=2).round().astype(np.uint8).tobytes()
    else:
        raise ValueError(f"camera mode must be 0 (grey) or 1 (RGB565), got {mode}")
    return bytes([mode, w, h]) + body


def camera_body_size(header: bytes | bytearray) -> int:
    """Bytes of pixels that follow a 3-byte -'I' header."""
    mode, w, h = header[0], header[1], header[2]
    if mode not in (CAMERA_GREY, CAMERA_RGB565) or w == 0 or h == 0:
        raise ValueError(f"implausible camera header mode={mode} width={w} height={h}")
    return w * h * (2 if mode == CAMERA_RGB565 else 1)


def decode_camera(header: bytes | bytearray, body: bytes | bytearray) -> npt.NDArray[np.uint8]:
    """An -'I' reply → an upright H×W×3 uint8 image (grey is copied to all channels)."""
    mode, w, h = header[0], header[1], header[2]
    size = camera_body_size(header)
    if len(body) != size:
        raise ValueError(f"a {w}×{h} image in mode {mode} has {size} bytes, got {len(body)}")
    if mode == CAMERA_RGB565:
        return rgb565_decode(body, w, h)
    grey = np.frombuffer(bytes(body), dtype=np.uint8).reshape(h, w)
    return np.repeat(grey[:, :, None], 3, axis=2)


@dataclass
class RequestParser:
    """The robot's side: cuts the PC → robot stream into binary requests and ASCII lines.

    :meth:`feed` returns what became complete: ``("binary", [(cmd, params), ...])`` when
    a zero terminator ends a binary sequence, or ``("ascii", "D,100,100")`` for a text
    line. Zero bytes outside a sequence are ignored, as on the robot.
    """

    _buffer: bytearray = field(default_factory=bytearray, repr=False)

    def feed(self, data: bytes | bytearray | memoryview) -> list[tuple[str, object]]:
        self._buffer.extend(data)
        out: list[tuple[str, object]] = []
        buf = self._buffer
        while buf:
            first = buf[0]
            if first == TERMINATOR:
                del buf[:1]
                continue
            if first < 0x80:  # ASCII line
                end = -1
                for i, b in enumerate(buf):
                    if b in (0x0D, 0x0A):
                        end = i
                        break
                if end < 0:
                    break
                line = bytes(buf[:end]).decode("ascii", errors="replace").strip()
                del buf[: end + 1]
                if line:
                    out.append(("ascii", line))
                continue
            items: list[tuple[int, bytes]] = []
            i = 0
            complete = False
            while i < len(buf):
                cmd = buf[i]
                if cmd == TERMINATOR:
                    complete = True
                    i += 1
                    break
                n = PARAMETER_SIZES.get(cmd, 0)
                if i + 1 + n > len(buf):
                    break
                items.append((cmd, bytes(buf[i + 1 : i + 1 + n])))
                i += 1 + n
            if not complete:
                break
            del buf[:i]
            out.append(("binary", items))
        return out
