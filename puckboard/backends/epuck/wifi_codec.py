"""The e-puck2 Wi-Fi protocol as bytes (pure: no sockets here).

The robot (selector 15, Wi-Fi firmwares on both processors) is a TCP server on port
1000. Every packet starts with a one-byte id:

* PC → robot **0x80** command, 20 bytes after the id: byte 1 requests the streams
  (bit0 image, bit1 sensors), bytes 2..20 are the actuator block
  (:class:`~puckboard.backends.epuck.blocks.ActuatorBlock`: settings, left and right speed
  int16 LE steps/s, LED bits, 4 × RGB, sound).
* robot → PC **0x01** image: 38400 bytes, a 160×120 RGB565 frame (QQVGA);
  **0x02** sensors: the 104-byte sensor block; **0x03** empty: the acknowledgement when
  the command requested neither stream.

The robot answers each command with the packets it asked for, so a client sends one
command and reads packets until it has them. :class:`PacketFramer` cuts an incoming byte
stream into packets and, when the stream is out of step (a byte that is no packet id),
skips ahead to the next plausible id and counts what it skipped — the resynchronisation
that keeps one bad byte from turning every later reading into nonsense.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from .blocks import ACTUATOR_BLOCK_SIZE, SENSOR_BLOCK_WIFI_SIZE, ActuatorBlock, SensorBlock
from .units import rgb565_decode, rgb565_encode

__all__ = [
    "COMMAND",
    "COMMAND_SIZE",
    "DEFAULT_PORT",
    "EMPTY",
    "EMPTY_PACKET",
    "IMAGE",
    "IMAGE_HEIGHT",
    "IMAGE_SIZE",
    "IMAGE_WIDTH",
    "PAYLOAD_SIZES",
    "REQUEST_IMAGE",
    "REQUEST_SENSORS",
    "SENSORS",
    "CommandFramer",
    "PacketFramer",
    "WifiCommand",
    "decode_image",
    "encode_image_packet",
    "encode_sensor_packet",
]

DEFAULT_PORT = 1000

COMMAND = 0x80
IMAGE = 0x01
SENSORS = 0x02
EMPTY = 0x03

REQUEST_IMAGE = 0x01
REQUEST_SENSORS = 0x02

IMAGE_WIDTH = 160
IMAGE_HEIGHT = 120
IMAGE_SIZE = IMAGE_WIDTH * IMAGE_HEIGHT * 2  # 38400
COMMAND_SIZE = 2 + ACTUATOR_BLOCK_SIZE  # id, request, 19-byte block = 21

PAYLOAD_SIZES: dict[int, int] = {IMAGE: IMAGE_SIZE, SENSORS: SENSOR_BLOCK_WIFI_SIZE, EMPTY: 0}
"""Payload length (after the id byte) of each robot → PC packet."""

EMPTY_PACKET = bytes([EMPTY])


@dataclass(frozen=True)
class WifiCommand:
    """One 0x80 command: what to drive and which streams to send back."""

    actuators: ActuatorBlock = field(default_factory=ActuatorBlock)
    image: bool = False
    sensors: bool = False

    @property
    def request(self) -> int:
        return (REQUEST_IMAGE if self.image else 0) | (REQUEST_SENSORS if self.sensors else 0)

    def encode(self) -> bytes:
        return bytes([COMMAND, self.request]) + self.actuators.encode()

    @classmethod
    def decode(cls, data: bytes | bytearray | memoryview) -> WifiCommand:
        if len(data) != COMMAND_SIZE or data[0] != COMMAND:
            raise ValueError(
                f"a Wi-Fi command is {COMMAND_SIZE} bytes starting with 0x{COMMAND:02x}, "
                f"got {len(data)} bytes starting with {bytes(data[:1]).hex() or 'nothing'}"
            )
        request = data[1]
        return cls(
            actuators=ActuatorBlock.decode(data[2:]),
            image=bool(request & REQUEST_IMAGE),
            sensors=bool(request & REQUEST_SENSORS),
        )


def encode_sensor_packet(block: SensorBlock) -> bytes:
    """Packet 0x02 as the robot sends it."""
    return bytes([SENSORS]) + block.encode(wifi=True)


def encode_image_packet(pixels: npt.NDArray[np.uint8]) -> bytes:
    """Packet 0x01 from a 120×160×3 upright image."""
    if pixels.shape != (IMAGE_HEIGHT, IMAGE_WIDTH, 3):
        raise ValueError(
            f"the Wi-Fi image is {IMAGE_WIDTH}×{IMAGE_HEIGHT} RGB, got shape {pixels.shape}"
        )
    return bytes([IMAGE]) + rgb565_encode(pixels)


def decode_image(payload: bytes | bytearray | memoryview) -> npt.NDArray[np.uint8]:
    """The 38400-byte payload of packet 0x01 → a 120×160×3 upright uint8 image."""
    return rgb565_decode(payload, IMAGE_WIDTH, IMAGE_HEIGHT)


@dataclass
class PacketFramer:
    """Cuts the robot → PC byte stream into ``(id, payload)`` packets.

    Feed bytes as they arrive; :meth:`packets` returns the complete packets so far. A
    byte that is not a packet id is skipped (counted in :attr:`skipped`): the stream
    resynchronises at the next id. A sensor payload that fails the plausibility check
    is dropped too and counted in :attr:`rejected`, since it means the id byte we
    trusted was really part of something else.
    """

    skipped: int = 0
    rejected: int = 0
    _buffer: bytearray = field(default_factory=bytearray, repr=False)

    def feed(self, data: bytes | bytearray | memoryview) -> None:
        self._buffer.extend(data)

    def pending(self) -> int:
        """Bytes buffered but not yet part of a complete packet."""
        return len(self._buffer)

    def needed(self) -> int:
        """How many more bytes the packet being assembled needs (at least 1)."""
        buf = self._buffer
        if not buf or buf[0] not in PAYLOAD_SIZES:
            return 1
        return max(1, 1 + PAYLOAD_SIZES[buf[0]] - len(buf))

    def packets(self) -> list[tuple[int, bytes]]:
        out: list[tuple[int, bytes]] = []
        buf = self._buffer
        while buf:
            pid = buf[0]
            size = PAYLOAD_SIZES.get(pid)
            if size is None:
                # Out of step: drop bytes up to the next byte that could start a packet.
                nxt = _next_id(buf, 1)
                self.skipped += nxt
                del buf[:nxt]
                continue
            if len(buf) < 1 + size:
                break
            payload = bytes(buf[1 : 1 + size])
            if pid == SENSORS:
                try:
                    SensorBlock.decode(payload)
                except ValueError:
                    self.rejected += 1
                    self.skipped += 1
                    del buf[:1]
                    continue
            del buf[: 1 + size]
            out.append((pid, payload))
        return out

    def clear(self) -> None:
        self._buffer.clear()


def _next_id(buf: bytearray, start: int) -> int:
    for i in range(start, len(buf)):
        if buf[i] in PAYLOAD_SIZES:
            return i
    return len(buf)


@dataclass
class CommandFramer:
    """The robot's side: cuts the PC → robot stream into :class:`WifiCommand` s.

    Bytes that cannot start a command are skipped and counted, as the robot's radio
    module does, so a client that sent garbage is answered again once it sends a
    proper command.
    """

    skipped: int = 0
    _buffer: bytearray = field(default_factory=bytearray, repr=False)

    def feed(self, data: bytes | bytearray | memoryview) -> None:
        self._buffer.extend(data)

    def commands(self) -> list[WifiCommand]:
        out: list[WifiCommand] = []
        buf = self._buffer
        while buf:
            if buf[0] != COMMAND:
                nxt = buf.find(bytes([COMMAND]))
                nxt = len(buf) if nxt < 0 else nxt
                self.skipped += nxt
                del buf[:nxt]
                continue
            if len(buf) < COMMAND_SIZE:
                break
            out.append(WifiCommand.decode(bytes(buf[:COMMAND_SIZE])))
            del buf[:COMMAND_SIZE]
        return out
