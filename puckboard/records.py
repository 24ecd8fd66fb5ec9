"""Typed sensor records: what an adapter writes to the blackboard, one class per sensor.

The source framework handed students bare arrays and made them remember which index was
which sensor; here every reading is a small immutable record with named fields. Arrays
inside records are read-only copies, so a record can be shared between threads safely.

Units are SI. Proximity comes twice, because users need both views:

* ``distance`` (m): V-REP semantics. A sensor that sees nothing within
  ``range`` reports exactly ``range`` (0.05 m by default); a smaller value means an
  obstacle at that distance. Controllers written for V-REP read this.
* ``raw``: the e-puck's own scale, 0 (nothing) .. 4095 (touching), through the response
  curve calibrated on the real robot. Students moving to the real robot read this.

Array order is always the real e-puck's: ps0..ps7, clockwise seen from above, starting
at the front-right sensor. The V-REP model numbers its sensors 1..8 clockwise starting
at the *left* side sensor; :data:`VREP_ORDER` maps between the two.

=====  ==================  ============  ========================
index  name                real e-puck   V-REP model
=====  ==================  ============  ========================
0      ``front_right``     ps0           ePuck_proxSensor4
1      ``diagonal_right``  ps1           ePuck_proxSensor5
2      ``right``           ps2           ePuck_proxSensor6
3      ``rear_right``      ps3           ePuck_proxSensor7
4      ``rear_left``       ps4           ePuck_proxSensor8
5      ``left``            ps5           ePuck_proxSensor1
6      ``diagonal_left``   ps6           ePuck_proxSensor2
7      ``front_left``      ps7           ePuck_proxSensor3
=====  ==================  ============  ========================
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np
import numpy.typing as npt

from .errors import NonFiniteError

_R = TypeVar("_R")

__all__ = [
    "GRAVITY",
    "GROUND_NAMES",
    "PROX_NAMES",
    "VREP_ORDER",
    "Acceleration",
    "AngularVelocity",
    "CameraImage",
    "Ground",
    "Light",
    "Pose",
    "Proximity",
    "Sensor",
    "WheelCommand",
    "WheelEncoders",
    "WheelSpeeds",
]

PROX_NAMES: tuple[str, ...] = (
    "front_right",
    "diagonal_right",
    "right",
    "rear_right",
    "rear_left",
    "left",
    "diagonal_left",
    "front_left",
)
"""Names of the 8 IR proximity sensors, in real e-puck order (ps0..ps7)."""

VREP_ORDER: tuple[int, ...] = (5, 6, 7, 0, 1, 2, 3, 4)
"""``VREP_ORDER[k]`` is the ps index of V-REP's ``ePuck_proxSensor{k+1}``."""

#: Standard gravity (m/s², the CGPM's conventional value rounded as the e-puck firmware
#: and the simulator use it): what a resting accelerometer reads along z.
GRAVITY = 9.81

GROUND_NAMES: tuple[str, ...] = ("left", "centre", "right")
"""Names of the 3 ground sensors, gs0..gs2."""


class Sensor(str, enum.Enum):
    """The sensors an adapter can read; the value is the blackboard key it writes."""

    PROXIMITY = "proximity"
    GROUND = "ground"
    LIGHT = "light"
    ACCELERATION = "acceleration"
    GYRO = "gyro"
    ENCODERS = "encoders"
    WHEEL_SPEEDS = "wheel_speeds"
    POSE = "pose"
    CAMERA = "camera"

    @property
    def key(self) -> str:
        """The blackboard key (relative to the robot's namespace)."""
        return self.value


#: numpy's float64 dtype: arrays of native float64 share it, so one identity test tells
#: the world's rows (any other array takes np.array's general path, as correct).
_FLOAT64 = np.dtype(np.float64)


def _frozen_array(values: Any, n: int, what: str) -> tuple[np.ndarray, list[float]]:
    """A read-only copy of ``values`` as ``n`` finite numbers, and the numbers as a list
    (for a record's own checks), or a ValueError naming ``what``.

    The checks run on a Python list: for 3 or 8 values that is several times cheaper than
    numpy's reductions, and records are built for every robot on every control cycle. A
    sum of finite numbers is finite unless it overflows, so one sum clears the usual
    case and only a sum that is not finite looks at each number.
    """
    if type(values) is np.ndarray and values.dtype is _FLOAT64:
        arr = values.copy()  # the world's rows: a copy without np.array's conversions
    else:
        arr = np.array(values, dtype=np.float64, copy=True)
    if arr.shape != (n,):
        raise ValueError(f"{what} needs {n} values, got an array of shape {arr.shape}")
    listed: list[float] = arr.tolist()
    if not math.isfinite(sum(listed)) and not all(map(math.isfinite, listed)):
        raise ValueError(f"{what} must be finite numbers, got {listed}")
    arr.setflags(write=False)
    return arr, listed


def _check_finite(cls_name: str, **values: float) -> None:
    for name, value in values.items():
        if not isinstance(value, (int, float, np.floating, np.integer)) or not math.isfinite(value):
            raise NonFiniteError(f"{cls_name}.{name} must be a finite number, got {value!r}")


def _store(record: object, fields: dict[str, Any]) -> None:
    """Set a frozen record's fields, which its ``__init__`` has checked, in one step.

    A frozen dataclass's own ``__init__`` sets them one at a time through
    ``object.__setattr__``; for the records built for every robot on every control cycle
    that cost more than checking them."""
    object.__setattr__(record, "__dict__", fields)


def _finite_floats(*values: float) -> bool:
    """Whether every value is a plain finite float: the usual case of a record built
    every cycle, cleared without :func:`_check_finite`'s keyword loop (anything else
    gets that full check, and its error)."""
    for value in values:
        if type(value) is not float or not -math.inf < value < math.inf:
            return False
    return True


class _Named:
    """Named read access to an 8- or 3-element array, e.g. ``prox.front_left``."""

    _names: tuple[str, ...] = ()
    _field: str = ""

    def __getattr__(self, name: str) -> float:
        names = type(self)._names
        if name in names:
            return float(getattr(self, type(self)._field)[names.index(name)])
        raise AttributeError(
            f"{type(self).__name__} has no attribute {name!r}; sensor names are: {', '.join(names)}"
        )

    def as_dict(self) -> dict[str, float]:
        """The primary values by sensor name."""
        values = getattr(self, type(self)._field)
        return {n: float(v) for n, v in zip(type(self)._names, values)}


@dataclass(frozen=True, eq=False, init=False)
class Proximity(_Named):
    """The 8 IR proximity sensors, in ps0..ps7 order.

    ``distance`` is in metres and equals ``range`` where nothing is detected; ``raw`` is
    the e-puck scale (0 nothing .. 4095 touching). Read one sensor by name:
    ``prox.front_left`` is the distance of ps7, ``prox.raw_of("front_left")`` its raw value.
    """

    distance: npt.NDArray[np.float64]
    raw: npt.NDArray[np.float64]
    range: float = 0.05

    _names = PROX_NAMES
    _field = "distance"

    def __init__(self, distance: Any, raw: Any, range: float = 0.05) -> None:
        distance, distances = _frozen_array(distance, 8, "Proximity.distance")
        raw, _ = _frozen_array(raw, 8, "Proximity.raw")
        if not _finite_floats(range):
            _check_finite("Proximity", range=range)
        if range <= 0:
            raise ValueError(f"Proximity.range must be positive (m), got {range}")
        if min(distances) < 0 or max(distances) > range + 1e-9:
            raise ValueError(
                f"Proximity.distance must lie in [0, range={range}] m, got {distances}"
            )
        _store(self, {"distance": distance, "raw": raw, "range": range})

    def raw_of(self, name: str) -> float:
        """Raw e-puck value of one sensor by name."""
        return float(self.raw[_index(PROX_NAMES, name)])

    def detected(self, name: str) -> bool:
        """True when the named sensor sees something within its range."""
        return bool(self.distance[_index(PROX_NAMES, name)] < self.range)

    def vrep(self) -> npt.NDArray[np.float64]:
        """Distances in the V-REP model's order (ePuck_proxSensor1..8)."""
        return self.distance[list(VREP_ORDER)]

    @classmethod
    def nothing(cls, range: float = 0.05) -> Proximity:
        """A reading with no obstacle anywhere."""
        return cls(np.full(8, range), np.zeros(8), range)


@dataclass(frozen=True, eq=False, init=False)
class Ground(_Named):
    """The 3 ground sensors gs0 (left), gs1 (centre), gs2 (right).

    ``value`` is V-REP's 0..1 brightness (a dark line reads below 0.5); ``raw`` is the
    e-puck scale (0 black .. 1023 white).
    """

    value: npt.NDArray[np.float64]
    raw: npt.NDArray[np.float64]

    _names = GROUND_NAMES
    _field = "value"

    def __init__(self, value: Any, raw: Any) -> None:
        value, values = _frozen_array(value, 3, "Ground.value")
        raw, _ = _frozen_array(raw, 3, "Ground.raw")
        if min(values) < 0 or max(values) > 1:
            raise ValueError(f"Ground.value must lie in [0, 1], got {values}")
        _store(self, {"value": value, "raw": raw})

    def dark(self, threshold: float = 0.5) -> npt.NDArray[np.bool_]:
        """Which sensors see the line (value below ``threshold``)."""
        return self.value < threshold


@dataclass(frozen=True, eq=False)
class Light(_Named):
    """Ambient light at the 8 IR sensors (ps order), e-puck scale: 0 bright .. 4095 dark."""

    raw: npt.NDArray[np.float64]

    _names = PROX_NAMES
    _field = "raw"

    def __post_init__(self) -> None:
        object.__setattr__(self, "raw", _frozen_array(self.raw, 8, "Light.raw")[0])


@dataclass(frozen=True, init=False)
class Acceleration:
    """Linear acceleration in the robot frame (m/s²), gravity included on z."""

    x: float
    y: float
    z: float

    def __init__(self, x: float, y: float, z: float) -> None:
        if not _finite_floats(x, y, z):
            _check_finite("Acceleration", x=x, y=y, z=z)
        _store(self, {"x": x, "y": y, "z": z})


@dataclass(frozen=True, init=False)
class AngularVelocity:
    """Angular velocity in the robot frame (rad/s), as a gyroscope measures it.

    Axes as for :class:`Acceleration`: x forward, y left, z up, so ``z`` is the yaw rate
    and is positive when the robot turns counter-clockwise seen from above. Unlike a
    turn rate computed from the wheels, it is what the body actually did: a wheel that
    slips on the floor fools the encoders, not the gyro.
    """

    x: float
    y: float
    z: float

    def __init__(self, x: float, y: float, z: float) -> None:
        if not _finite_floats(x, y, z):
            _check_finite("AngularVelocity", x=x, y=y, z=z)
        _store(self, {"x": x, "y": y, "z": z})


@dataclass(frozen=True, init=False)
class WheelEncoders:
    """Accumulated wheel rotation (rad) since the adapter opened; never wraps."""

    left: float
    right: float

    def __init__(self, left: float, right: float) -> None:
        if not _finite_floats(left, right):
            _check_finite("WheelEncoders", left=left, right=right)
        _store(self, {"left": left, "right": right})


@dataclass(frozen=True, init=False)
class WheelSpeeds:
    """Measured (or, where nothing measures them, commanded) wheel speeds (rad/s)."""

    left: float
    right: float

    def __init__(self, left: float, right: float) -> None:
        if not _finite_floats(left, right):
            _check_finite("WheelSpeeds", left=left, right=right)
        _store(self, {"left": left, "right": right})


@dataclass(frozen=True, init=False)
class WheelCommand:
    """A wheel speed command (rad/s), as produced by a behaviour layer."""

    left: float
    right: float

    def __init__(self, left: float, right: float) -> None:
        if not _finite_floats(left, right):
            _check_finite("WheelCommand", left=left, right=right)
        _store(self, {"left": left, "right": right})

    @classmethod
    def stop(cls) -> WheelCommand:
        return cls(0.0, 0.0)


@dataclass(frozen=True, init=False)
class Pose:
    """Planar pose: position (m) and heading (rad, counter-clockwise from world x).

    ``ground_truth`` is True when the pose comes from the simulator's own state rather
    than from an estimate: a real robot never has one.
    """

    x: float
    y: float
    theta: float
    ground_truth: bool = False

    def __init__(self, x: float, y: float, theta: float, ground_truth: bool = False) -> None:
        if not _finite_floats(x, y, theta):
            _check_finite("Pose", x=x, y=y, theta=theta)
        _store(self, {"x": x, "y": y, "theta": theta, "ground_truth": ground_truth})


@dataclass(frozen=True, eq=False)
class CameraImage:
    """An upright colour image: an H×W×3 uint8 array, row 0 at the top."""

    pixels: npt.NDArray[np.uint8]

    def __post_init__(self) -> None:
        arr = np.array(self.pixels, copy=True)
        if arr.ndim != 3 or arr.shape[2] != 3 or arr.dtype != np.uint8:
            raise ValueError(
                "CameraImage.pixels must be an H×W×3 uint8 array, got "
                f"shape {arr.shape} dtype {arr.dtype}"
            )
        arr.setflags(write=False)
        object.__setattr__(self, "pixels", arr)

    @property
    def height(self) -> int:
        return int(self.pixels.shape[0])

    @property
    def width(self) -> int:
        return int(self.pixels.shape[1])


def _index(names: tuple[str, ...], name: str) -> int:
    try:
        return names.index(name)
    except ValueError:
        raise KeyError(f"unknown sensor name {name!r}; known: {', '.join(names)}") from None


RECORD_TYPES: dict[Sensor, type] = {
    Sensor.PROXIMITY: Proximity,
    Sensor.GROUND: Ground,
    Sensor.LIGHT: Light,
    Sensor.ACCELERATION: Acceleration,
    Sensor.GYRO: AngularVelocity,
    Sensor.ENCODERS: WheelEncoders,
    Sensor.WHEEL_SPEEDS: WheelSpeeds,
    Sensor.POSE: Pose,
    Sensor.CAMERA: CameraImage,
}
"""The record class each sensor key holds; used to declare the blackboard's schemas."""
