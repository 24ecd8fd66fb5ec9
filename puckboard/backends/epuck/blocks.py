"""The two byte blocks both e-puck2 protocols share: all sensors, and all actuators.

The e-puck2 firmware's advanced sercom v2 has an "all sensors" command (0x08, 103 bytes)
and a "set all actuators" command (0x09, 19 bytes of parameters). The Wi-Fi radio
module builds its TCP packets from the same blocks: the sensor packet 0x02 is the
103-byte block with the button state in byte 102 (where the serial block has a spare
zero) plus one reserved byte, and the command packet 0x80 is a request byte followed
by the 19-byte actuator block. So one codec serves both transports.

Layout of the sensor block (offsets in bytes, every multi-byte field little-endian —
the firmware writes the low byte first even where its comment says "big endian"):

======  ==========================================================
0–5     accelerometer x, y, z (int16, ≈768 counts/g on e-puck2)
6–17    acceleration magnitude, orientation (°), inclination (°) (float32)
18–23   gyro x, y, z (int16)
24–35   magnetometer x, y, z (float32, µT)
36      temperature (int8, °C)
37–52   8 × IR proximity, calibrated (int16; ≈0 free .. ≈4000 touching)
53–68   8 × IR ambient (int16; 0 bright .. 4095 dark)
69–70   ToF distance (uint16, mm)
71–78   4 × microphone volume (uint16)
79–82   left, right step counters (int16, wrap around)
83–84   battery (uint16, raw ADC)
85      micro-SD state
86–88   TV remote: check, address, data
89      selector position 0..15
90–95   3 × ground proximity (uint16; 0 black .. 1023 white)
96–101  3 × ground ambient (uint16)
102     Wi-Fi: button (1 pressed); serial 0x08: spare byte (0)
103     Wi-Fi only: reserved
======  ==========================================================

Sources: e-puck2_main-processor ``src/epuck1x/Asercom2.c`` (cases 0x08 and 0x09) and
GCtronic's "e-puck2 PC side development" Wi-Fi protocol section.
"""

from __future__ import annotations

import math
import struct
from dataclasses import dataclass

__all__ = [
    "ACTUATOR_BLOCK_SIZE",
    "SENSOR_BLOCK_SERIAL_SIZE",
    "SENSOR_BLOCK_WIFI_SIZE",
    "ActuatorBlock",
    "ImplausibleDataError",
    "SensorBlock",
    "Sound",
]

SENSOR_BLOCK_SERIAL_SIZE = 103
SENSOR_BLOCK_WIFI_SIZE = 104
ACTUATOR_BLOCK_SIZE = 19

# acc(3h) 3 floats, gyro(3h) mag(3f) temp(b) prox(8h) ambient(8h) tof(H) mic(4H) steps(2h)
# battery(H) sd(B) tv(3B) selector(B) ground(3H) ground ambient(3H) byte102(B)
_SENSOR_FMT = struct.Struct("<3h3f3h3fb8h8hH4H2hHB3BB3H3HB")
assert _SENSOR_FMT.size == SENSOR_BLOCK_SERIAL_SIZE

_ACTUATOR_FMT = struct.Struct("<Bhh B 12B B")
assert _ACTUATOR_FMT.size == ACTUATOR_BLOCK_SIZE


class ImplausibleDataError(ValueError):
    """Bytes decoded into values the robot cannot produce: we are out of step with it."""


class Sound:
    """Bits of the actuator block's sound byte (several may be set)."""

    MARIO = 0x01
    UNDERWORLD = 0x02
    STAR_WARS = 0x04
    TONE_4KHZ = 0x08
    TONE_10KHZ = 0x10
    STOP = 0x20


@dataclass(frozen=True)
class SensorBlock:
    """Every sensor of the e-puck2 as the robot encodes it (raw units, no conversion)."""

    acc: tuple[int, int, int] = (0, 0, 0)
    acceleration: float = 0.0
    orientation: float = 0.0
    inclination: float = 0.0
    gyro: tuple[int, int, int] = (0, 0, 0)
    magnetometer: tuple[float, float, float] = (0.0, 0.0, 0.0)
    temperature: int = 25
    proximity: tuple[int, ...] = (0,) * 8
    ambient: tuple[int, ...] = (4000,) * 8
    tof_mm: int = 2000
    microphones: tuple[int, int, int, int] = (0, 0, 0, 0)
    steps: tuple[int, int] = (0, 0)
    battery: int = 3500
    sd_state: int = 0
    tv_remote: tuple[int, int, int] = (0, 0, 0)
    selector: int = 15
    ground: tuple[int, int, int] = (1000, 1000, 1000)
    ground_ambient: tuple[int, int, int] = (1000, 1000, 1000)
    button: int = 0

    def encode(self, *, wifi: bool) -> bytes:
        """The block's bytes: 104 for the Wi-Fi packet 0x02, 103 for the serial 0x08."""
        payload = _SENSOR_FMT.pack(
            *self.acc,
            self.acceleration,
            self.orientation,
            self.inclination,
            *self.gyro,
            *self.magnetometer,
            self.temperature,
            *self.proximity,
            *self.ambient,
            self.tof_mm,
            *self.microphones,
            *self.steps,
            self.battery,
            self.sd_state,
            *self.tv_remote,
            self.selector,
            *self.ground,
            *self.ground_ambient,
            self.button if wifi else 0,
        )
        return payload + b"\x00" if wifi else payload

    @classmethod
    def decode(cls, data: bytes | bytearray | memoryview, *, check: bool = True) -> SensorBlock:
        """Parse a 103-byte (serial) or 104-byte (Wi-Fi) block.

        With ``check`` the values are tested for plausibility (selector 0..15, 12-bit
        ambient light, 10/12-bit ground readings); a failure raises
        :class:`ImplausibleDataError`, the sign that the byte stream is out of step.
        """
        n = len(data)
        if n not in (SENSOR_BLOCK_SERIAL_SIZE, SENSOR_BLOCK_WIFI_SIZE):
            raise ValueError(
                f"a sensor block has {SENSOR_BLOCK_SERIAL_SIZE} (serial) or "
                f"{SENSOR_BLOCK_WIFI_SIZE} (Wi-Fi) bytes, got {n}"
            )
        v = _SENSOR_FMT.unpack_from(bytes(data), 0)
        block = cls(
            acc=(v[0], v[1], v[2]),
            acceleration=v[3],
            orientation=v[4],
            inclination=v[5],
            gyro=(v[6], v[7], v[8]),
            magnetometer=(v[9], v[10], v[11]),
            temperature=v[12],
            proximity=tuple(v[13:21]),
            ambient=tuple(v[21:29]),
            tof_mm=v[29],
            microphones=(v[30], v[31], v[32], v[33]),
            steps=(v[34], v[35]),
            battery=v[36],
            sd_state=v[37],
            tv_remote=(v[38], v[39], v[40]),
            selector=v[41],
            ground=(v[42], v[43], v[44]),
            ground_ambient=(v[45], v[46], v[47]),
            button=v[48] if n == SENSOR_BLOCK_WIFI_SIZE else 0,
        )
        if check:
            block.check_plausible()
            if n == SENSOR_BLOCK_SERIAL_SIZE and v[48] != 0:
                raise ImplausibleDataError(
                    f"implausible sensor block: the spare byte 102 is {v[48]}, the robot sends 0"
                )
        return block

    def check_plausible(self) -> None:
        """Raise :class:`ImplausibleDataError` if a field is outside what the robot sends."""
        problems = []
        if not 0 <= self.selector <= 15:
            problems.append(f"selector {self.selector} (0..15)")
        if any(not -4096 <= p <= 4096 for p in self.proximity):
            problems.append(f"proximity {self.proximity} (-4096..4096)")
        if any(not 0 <= a <= 4096 for a in self.ambient):
            problems.append(f"ambient {self.ambient} (0..4096)")
        if any(g > 4096 for g in self.ground):
            problems.append(f"ground {self.ground} (0..4096)")
        if self.button not in (0, 1):
            problems.append(f"button {self.button} (0 or 1)")
        if not -40 <= self.temperature <= 100:
            problems.append(f"temperature {self.temperature} °C (-40..100)")
        floats = (self.acceleration, self.orientation, self.inclination, *self.magnetometer)
        if not all(math.isfinite(f) for f in floats):
            problems.append(f"non-finite IMU values {floats}")
        if problems:
            raise ImplausibleDataError("implausible sensor block: " + "; ".join(problems))


@dataclass(frozen=True)
class ActuatorBlock:
    """The 19-byte "set all actuators" block (serial 0x09, Wi-Fi command bytes 2..20).

    ``speeds`` are steps/s (int16). ``leds`` is a bit mask: bit0 LED1 (front), bit1 LED3
    (right), bit2 LED5 (back), bit3 LED7 (left), bit4 body, bit5 front LED. ``rgb`` holds
    LED2, LED4, LED6, LED8 as r, g, b each 0..100. ``settings``: bit0 calibrate the IR
    sensors, bit1 on-board obstacle avoidance, bit2 "speeds are step counters to set".
    """

    left: int = 0
    right: int = 0
    leds: int = 0
    rgb: tuple[int, ...] = (0,) * 12
    sound: int = 0
    settings: int = 0

    CALIBRATE_IR = 0x01
    OBSTACLE_AVOIDANCE = 0x02
    SET_STEPS = 0x04

    def __post_init__(self) -> None:
        if len(self.rgb) != 12:
            raise ValueError(f"rgb needs 12 values (4 LEDs × r, g, b), got {len(self.rgb)}")
        for name, value, lo, hi in (
            ("left", self.left, -0x8000, 0x7FFF),
            ("right", self.right, -0x8000, 0x7FFF),
            ("leds", self.leds, 0, 0xFF),
            ("sound", self.sound, 0, 0xFF),
            ("settings", self.settings, 0, 0xFF),
        ):
            if not lo <= value <= hi:
                raise ValueError(f"actuator field {name}={value} outside {lo}..{hi}")
        if any(not 0 <= c <= 255 for c in self.rgb):
            raise ValueError(f"rgb values must be bytes (0..100 used by the robot), got {self.rgb}")

    def encode(self) -> bytes:
        return _ACTUATOR_FMT.pack(
            self.settings, self.left, self.right, self.leds, *self.rgb, self.sound
        )

    @classmethod
    def decode(cls, data: bytes | bytearray | memoryview) -> ActuatorBlock:
        if len(data) != ACTUATOR_BLOCK_SIZE:
            raise ValueError(f"an actuator block has {ACTUATOR_BLOCK_SIZE} bytes, got {len(data)}")
        v = _ACTUATOR_FMT.unpack(bytes(data))
        return cls(settings=v[0], left=v[1], right=v[2], leds=v[3], rgb=tuple(v[4:16]), sound=v[16])
