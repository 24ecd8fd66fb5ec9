"""Unit conversions at the real robot's boundary: what the e-puck says ↔ SI.

The robot speaks motor steps, 12-bit ADC counts, 10-bit ground readings, raw
accelerometer and gyro counts, int16 step counters that wrap, and RGB565 images. Everything here
is a pure function (or, for the step counters, a tiny stateful unwrapper), so both the
adapter and the emulator use the very same conversions in opposite directions and the
tests can check that they are inverses.

Proximity model
---------------
The e-puck reports *calibrated* IR values: ``reflected − ambient − baseline``, where the
baseline is averaged at start-up (or on request) with nothing in front of the robot. So
a free sensor reads ≈0 and a touching one ≈4000; the e-puck2 firmware clamps at 0
(``get_calibrated_prox``: a reading below its baseline is 0, never negative).

The distance comes from the one conversion the simulator uses too,
:func:`~puckboard.ir_response.distance_from_calibrated` (re-exported here): the inverse
of the Webots e-puck table minus its far baseline, with values at or below the curve's
value at the profile's ``prox_max_distance`` (≈53 at 5 cm) reading exactly ``range``
(0.05 m), the V-REP convention every puckboard record follows. Real sensors differ from
robot to robot by tens of percent and depend on the obstacle's colour, so treat the
distance as an estimate and the raw value as the measurement.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from ...ir_response import calibrated_from_distance, distance_from_calibrated
from ...profile import RobotProfile
from ...records import GRAVITY

__all__ = [
    "ACC_COUNTS_PER_G",
    "GRAVITY",
    "GYRO_COUNTS_PER_DPS",
    "StepCounterUnwrapper",
    "acceleration_from_raw",
    "acceleration_to_raw",
    "angular_velocity_from_raw",
    "angular_velocity_to_raw",
    "calibrated_from_distance",
    "clamp_int16",
    "distance_from_calibrated",
    "ground_value_from_raw",
    "rad_s_to_steps_s",
    "rgb565_decode",
    "rgb565_encode",
    "steps_s_to_rad_s",
    "wrap_int16",
]

"""Standard gravity (m/s²) used to convert accelerometer counts."""

ACC_COUNTS_PER_G = 768.0
"""e-puck2 accelerometer counts per g in the all-sensors block and the Wi-Fi packet.

The firmware reduces the IMU's 16-bit reading (16384 counts/g at ±2 g) by
``(v >> 4) − (v >> 6)`` = 3/64 to mimic the e-puck1 (≈800 counts/g), which gives 768;
the Wi-Fi documentation's "±1500 for ±2 g" agrees. The e-puck1 reports ≈800 counts/g
around an offset of 2048; :func:`acceleration_from_raw` takes both as parameters.
"""

GYRO_COUNTS_PER_DPS = 131.0
"""e-puck2 gyro counts per °/s in the all-sensors block and the Wi-Fi packet.

The IMU (MPU-9250, or ICM-20948 on newer robots) runs at its ±250 °/s full scale, where
the MPU-9250 datasheet gives 131 LSB/(°/s) (32768 / 250 = 131.07, rounded); the e-puck2
firmware converts with the same 131 (``gyro_res`` in e-puck2_main-processor
``src/sensors/mpu9250.c``). The block carries the int16 reading minus the offset the
firmware measured at start-up (``getAllAxesGyro`` in ``src/epuck1x/acc_gyro/e_lsm330.c``),
so a robot standing still reads about 0.
"""


# -- wheels ------------------------------------------------------------------------------
def rad_s_to_steps_s(speed: float, profile: RobotProfile) -> int:
    """Wheel speed (rad/s) to the integer steps/s the motors take, rounded to nearest."""
    return int(round(profile.rad_to_steps(speed)))


def steps_s_to_rad_s(steps: float, profile: RobotProfile) -> float:
    """Motor steps/s to wheel speed (rad/s)."""
    return float(profile.steps_to_rad(steps))


class StepCounterUnwrapper:
    """Turns the robot's int16 step counters, which wrap every 65536 steps, into a
    continuous count.

    The counters wrap after ≈65 wheel revolutions (≈4 m of travel); a controller doing
    odometry must never see that jump. Between two readings a wheel can turn at most
    half the counter's range (32768 steps, 30 s at full speed), so the shortest signed
    difference is the true one. The first reading becomes zero: encoders count from the
    moment the adapter opened, as in the simulators.
    """

    __slots__ = ("_last", "_total")

    def __init__(self) -> None:
        self._last: tuple[int, int] | None = None
        self._total = [0, 0]

    def update(self, left: int, right: int) -> tuple[int, int]:
        """Feed the raw counters (any int, interpreted modulo 2¹⁶); return unwrapped steps."""
        raw = (left & 0xFFFF, right & 0xFFFF)
        if self._last is not None:
            for i in range(2):
                delta = (raw[i] - self._last[i]) & 0xFFFF
                if delta >= 0x8000:
                    delta -= 0x10000
                self._total[i] += delta
        self._last = raw
        return self._total[0], self._total[1]

    def reset(self) -> None:
        self._last = None
        self._total = [0, 0]


# -- ground, accelerometer ---------------------------------------------------------------
def ground_value_from_raw(
    raw: npt.ArrayLike, full_scale: float = 1023.0
) -> npt.NDArray[np.float64]:
    """Ground sensor reading (0 black .. 1023 white) → brightness 0..1, clipped."""
    return np.clip(np.asarray(raw, dtype=np.float64) / full_scale, 0.0, 1.0)


def acceleration_from_raw(
    raw: tuple[int, int, int], counts_per_g: float = ACC_COUNTS_PER_G, offset: float = 0.0
) -> tuple[float, float, float]:
    """Raw accelerometer counts → m/s² (e-puck2 all-sensors: offset 0, 768 counts/g)."""
    k = GRAVITY / counts_per_g
    return ((raw[0] - offset) * k, (raw[1] - offset) * k, (raw[2] - offset) * k)


def acceleration_to_raw(
    acc: tuple[float, float, float], counts_per_g: float = ACC_COUNTS_PER_G, offset: float = 0.0
) -> tuple[int, int, int]:
    """m/s² → raw accelerometer counts, the inverse of :func:`acceleration_from_raw`."""
    k = counts_per_g / GRAVITY
    out = [int(round(a * k + offset)) for a in acc]
    return (out[0], out[1], out[2])


def angular_velocity_from_raw(raw: tuple[int, int, int]) -> tuple[float, float, float]:
    """Raw e-puck2 gyro counts (IMU axes) → angular velocity (rad/s) in the robot frame.

    The axis mapping is inferred, not measured on a robot: the firmware's axis drawing
    for the e-puck2 IMU (``e_lsm330.c``) has the chip's -y pointing forward and -x to the
    right, so robot x (forward) = -y, robot y (left) = x, and z (up, right-handed) is the
    chip's z: a counter-clockwise turn seen from above gives z > 0. The yaw rate z is all
    the odometry uses; check its sign on your robot by turning it by hand.
    """
    k = math.radians(1.0) / GYRO_COUNTS_PER_DPS
    return (-raw[1] * k, raw[0] * k, raw[2] * k)


def angular_velocity_to_raw(rate: tuple[float, float, float]) -> tuple[int, int, int]:
    """Angular velocity (rad/s, robot frame) → raw gyro counts, saturated at ±250 °/s:
    the inverse of :func:`angular_velocity_from_raw`."""
    k = GYRO_COUNTS_PER_DPS / math.radians(1.0)
    x, y, z = rate
    return (clamp_int16(y * k), clamp_int16(-x * k), clamp_int16(z * k))


# -- camera ------------------------------------------------------------------------------
def rgb565_decode(
    data: bytes | bytearray | memoryview, width: int, height: int
) -> npt.NDArray[np.uint8]:
    """RGB565 bytes as the e-puck sends them → an upright H×W×3 uint8 image.

    Each pixel is two bytes, high byte first: ``RRRRRGGG GGGBBBBB``. As the e-puck's own
    tools do, the 5- and 6-bit channels are shifted up without filling the low bits
    (pure white reads 248, 252, 248).
    """
    expected = width * height * 2
    if len(data) != expected:
        raise ValueError(
            f"an RGB565 image of {width}×{height} needs {expected} bytes, got {len(data)}"
        )
    raw = np.frombuffer(bytes(data), dtype=np.uint8).reshape(height, width, 2)
    b0 = raw[..., 0]
    b1 = raw[..., 1]
    out = np.empty((height, width, 3), dtype=np.uint8)
    out[..., 0] = b0 & 0xF8
    out[..., 1] = ((b0 & 0x07) << 5) | ((b1 & 0xE0) >> 3)
    out[..., 2] = (b1 & 0x1F) << 3
    return out


def rgb565_encode(pixels: npt.NDArray[np.uint8]) -> bytes:
    """An H×W×3 uint8 image → RGB565 bytes, high byte first (what the robot sends)."""
    arr = np.asarray(pixels)
    if arr.ndim != 3 or arr.shape[2] != 3:
        raise ValueError(f"rgb565_encode needs an H×W×3 image, got shape {arr.shape}")
    p = arr.astype(np.uint16)
    r5 = p[..., 0] >> 3
    g6 = p[..., 1] >> 2
    b5 = p[..., 2] >> 3
    out = np.empty(arr.shape[:2] + (2,), dtype=np.uint8)
    out[..., 0] = ((r5 << 3) | (g6 >> 3)).astype(np.uint8)
    out[..., 1] = (((g6 & 0x07) << 5) | b5).astype(np.uint8)
    return out.tobytes()


def wrap_int16(value: int) -> int:
    """An integer as the robot's int16 counter would hold it (two's complement wrap)."""
    return ((int(value) + 0x8000) & 0xFFFF) - 0x8000


def clamp_int16(value: float) -> int:
    """Round and saturate to the int16 range (for speeds and sensor values on the wire)."""
    if not math.isfinite(value):
        raise ValueError(f"cannot send {value!r} as an int16")
    return max(-0x8000, min(0x7FFF, int(round(value))))
