"""Robot profiles: the e-puck's geometry and limits as data, and every unit conversion.

Sources disagree on the e-puck's dimensions (axle 51-56.5 mm, wheel radius 20-20.5 mm,
speed limit 1000, 1100 or 1200 steps/s), so the numbers live in one frozen record per
model instead of being scattered as literals. Everything public is SI: metres, radians,
seconds. The real robot speaks *steps*: its stepper motors make 1000 steps per wheel
revolution, and the conversions below are the only place where steps appear.

Frame convention (used everywhere in puckboard): x forward, y to the left, angles
counter-clockwise from the forward axis, seen from above.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

__all__ = [
    "EPUCK",
    "EPUCK1",
    "EPUCK2",
    "EPUCK_VREP",
    "NO_DETECTION_DISTANCE",
    "PROFILES",
    "RobotProfile",
    "SensorPose",
    "get_profile",
    "profile_names",
]


@dataclass(frozen=True)
class SensorPose:
    """Where a sensor sits on the robot: position (m) and heading (rad) in the robot frame."""

    x: float
    y: float
    heading: float


# -- the physical e-puck ------------------------------------------------------------------
# IR proximity sensors ps0..ps7 (real e-puck order: clockwise seen from above, starting at
# the front-right sensor) at the Webots e-puck model's positions and headings (Webots
# guide "Devices orientations", E-puck.proto). Why Webots: the distance→value table that
# turns a distance into a raw reading (puckboard.ir_response) is Webots' calibration, and
# its distances are measured from these positions, so table and positions go together.
# Spread of the sources (docs/profiles.md): GCtronic's ROS driver puts ps0 at
# (35, -10) mm / -10°, Enki at (30, -9) mm / -16°; headings -10..-17°, ±40..46°, ±90°,
# ±150..160°; ring radii 30-36 mm.
_WEBOTS_PROX = (
    (0.030, -0.010, -17.0),
    (0.022, -0.025, -46.0),
    (0.000, -0.031, -90.0),
    (-0.030, -0.015, -151.0),
    (-0.030, 0.015, 151.0),
    (0.000, 0.031, 90.0),
    (0.022, 0.025, 46.0),
    (0.030, 0.010, 17.0),
)
_PROX_POSES = tuple(SensorPose(x, y, math.radians(h)) for x, y, h in _WEBOTS_PROX)

# Ground sensors gs0 (left), gs1 (centre), gs2 (right): Webots' groundSensorsSlot at
# x = +30 mm, sensors 10 mm apart (E-puckGroundSensors.proto).
_GROUND_POSES = (
    SensorPose(0.030, 0.010, -math.pi / 2),
    SensorPose(0.030, 0.000, -math.pi / 2),
    SensorPose(0.030, -0.010, -math.pi / 2),
)

# -- V-REP's / CoppeliaSim's e-puck model (e-puck.ttm) --------------------------------------
# Decoded from four public scene files (the V-REP e-puck model reference, "Geometry"):
# ePuck_proxSensor1..8 in V-REP order (1 = left side, clockwise), (x mm, y mm, look °).
_VREP_PROX_BY_VREP_NUMBER = (
    (0.9, 34.8, 90.0),  # ePuck_proxSensor1 = ps5 (left)
    (22.7, 27.0, 45.0),  # ePuck_proxSensor2 = ps6
    (33.7, 9.6, 15.0),  # ePuck_proxSensor3 = ps7
    (33.7, -9.4, -15.0),  # ePuck_proxSensor4 = ps0
    (22.7, -27.0, -45.0),  # ePuck_proxSensor5 = ps1
    (0.9, -34.8, -90.0),  # ePuck_proxSensor6 = ps2 (right)
    (-28.0, -20.7, -145.0),  # ePuck_proxSensor7 = ps3
    (-28.0, 20.7, 145.0),  # ePuck_proxSensor8 = ps4
)
# records.VREP_ORDER without importing records: V-REP sensor k is ps (5, 6, 7, 0, ...)[k]
_PS_OF_VREP = (5, 6, 7, 0, 1, 2, 3, 4)
_VREP_PROX_POSES = tuple(
    SensorPose(x / 1000.0, y / 1000.0, math.radians(h))
    for _, (x, y, h) in sorted(zip(_PS_OF_VREP, _VREP_PROX_BY_VREP_NUMBER))
)
# ePuck_lightSensor: 29.8 mm ahead; the three pixels the child script sends sit at
# -10.3, -0.7 and +10.3 mm across, left to right (so y = +10.3, +0.7, -10.3 mm).
_VREP_GROUND_POSES = (
    SensorPose(0.0298, 0.0103, -math.pi / 2),
    SensorPose(0.0298, 0.0007, -math.pi / 2),
    SensorPose(0.0298, -0.0103, -math.pi / 2),
)

#: The distance (m) a proximity reading takes when nothing is detected: the controllers'
#: ``noDetectionDistance`` (V-REP's stock script and the thesis's Code 4.13). A convention
#: of the readings, not a property of any sensor (V-REP's detect up to 41.5 mm).
NO_DETECTION_DISTANCE = 0.05


@dataclass(frozen=True)
class RobotProfile:
    """Geometry, limits and sensor layout of one robot model.

    Attributes are SI. ``max_wheel_speed`` is the wheel's angular speed limit in rad/s;
    commands beyond it are clamped (with a warning) by every adapter.

    The proximity sensors follow ``prox_model``: ``"rays"`` (the physical robot: a fan of
    rays over ``prox_aperture`` through the calibrated response table, with noise) or
    ``"cone"`` (V-REP's proximity sensor: the exact distance to the nearest point of any
    object inside a cone of ``prox_aperture``, detected only between
    ``prox_min_distance`` and ``prox_max_distance``, no noise). Either way a reading of
    nothing is ``prox_range``, the controllers' no-detection distance.
    ``sources`` says where each number comes from (``puckboard profiles``).
    """

    name: str
    wheel_radius: float  # m
    axle_length: float  # m, distance between the wheels' contact points
    body_radius: float  # m, collision radius
    max_wheel_speed: float  # rad/s
    steps_per_revolution: int = 1000
    prox_range: float = NO_DETECTION_DISTANCE  # m; what a reading of "nothing" says
    prox_aperture: float = math.radians(15.0)  # rad, full opening angle of one IR sensor
    prox_model: str = "rays"
    prox_min_distance: float = 0.0  # m, nearest distance a sensor detects
    prox_max_distance: float = NO_DETECTION_DISTANCE  # m, farthest distance it reports
    prox_poses: tuple[SensorPose, ...] = _PROX_POSES
    ground_poses: tuple[SensorPose, ...] = _GROUND_POSES
    camera_fov: float = 0.84  # rad, horizontal field of view
    camera_height: float = 0.028  # m
    mass: float = 0.15  # kg
    has_gyro: bool = False
    camera_forward: float = 0.030  # m ahead of the axle's middle
    aliases: tuple[str, ...] = ()
    sources: dict[str, str] = field(default_factory=dict, compare=False, hash=False)
    extra: dict[str, float] = field(default_factory=dict, compare=False, hash=False)

    def __post_init__(self) -> None:
        if self.prox_model not in ("rays", "cone"):
            raise ValueError(f"prox_model must be 'rays' or 'cone', got {self.prox_model!r}")
        if not 0.0 <= self.prox_min_distance < self.prox_max_distance <= self.prox_range:
            raise ValueError(
                "need 0 <= prox_min_distance < prox_max_distance <= prox_range, got "
                f"{self.prox_min_distance}, {self.prox_max_distance}, {self.prox_range}"
            )

    # -- conversions -------------------------------------------------------------------
    @property
    def rad_per_step(self) -> float:
        """Wheel rotation of one motor step (rad)."""
        return 2.0 * math.pi / self.steps_per_revolution

    def steps_to_rad(self, steps: float) -> float:
        """Motor steps (or steps/s) to wheel angle (rad, or rad/s)."""
        return steps * self.rad_per_step

    def rad_to_steps(self, rad: float) -> float:
        """Wheel angle (rad, or rad/s) to motor steps (or steps/s); not rounded."""
        return rad / self.rad_per_step

    def rad_s_to_m_s(self, wheel_speed: float) -> float:
        """Wheel angular speed (rad/s) to ground speed of that wheel (m/s)."""
        return wheel_speed * self.wheel_radius

    def m_s_to_rad_s(self, speed: float) -> float:
        """Ground speed of a wheel (m/s) to its angular speed (rad/s)."""
        return speed / self.wheel_radius

    @property
    def max_speed(self) -> float:
        """Top forward speed of the robot (m/s)."""
        return self.max_wheel_speed * self.wheel_radius

    def body_velocity(self, left: float, right: float) -> tuple[float, float]:
        """Wheel speeds (rad/s) to body velocity: (forward m/s, turn rate rad/s)."""
        v_left = left * self.wheel_radius
        v_right = right * self.wheel_radius
        return (v_left + v_right) / 2.0, (v_right - v_left) / self.axle_length

    def wheel_speeds(self, forward: float, turn_rate: float) -> tuple[float, float]:
        """Body velocity (m/s, rad/s) to wheel speeds (rad/s): the inverse of ``body_velocity``."""
        half = turn_rate * self.axle_length / 2.0
        return (forward - half) / self.wheel_radius, (forward + half) / self.wheel_radius


_PHYSICAL_SOURCES = {
    "wheel_radius": "20.5 mm: Webots guide and e-puck.org ('about 41 mm' diameter); "
    "spread 20-20.5 mm (Webots proto wheel 20 mm, GCtronic ROS driver 20 mm)",
    "axle_length": "53 mm: e-puck.org ('about 53 mm'), ARGoS; spread 51 (Enki) - 56.5 mm",
    "body_radius": "37 mm: Webots collision cylinder, e-puck.org 7.4 cm overall; drivers use 35 mm",
    "prox_poses": "Webots E-puck.proto positions and guide headings (±17°, ±46°, ±90°, ±151°); "
    "the calibration table's distances are measured from them; spread: GCtronic driver "
    "±10°/±40°/±160° at 36 mm, Enki ±16°/±45°/±150° at 31 mm",
    "prox_aperture": "15°: GCtronic's per-sensor aperture (Webots proto 0.1 rad)",
    "prox_model": "rays through the Webots E-puckDistanceSensor table, calibrated on a real "
    "e-puck (puckboard.ir_response), with its relative noise",
    "prox_max_distance": "50 mm reported (the table: 120 at 5 cm, 67 ambient baseline at 7 cm); "
    "= the controllers' no-detection distance",
    "ground_poses": "Webots E-puckGroundSensors: x = 30 mm, 10 mm apart",
    "camera": "Webots: 30 mm ahead, 28 mm high, field of view 0.84 rad",
    "max_wheel_speed": "e-puck2 firmware MOTOR_SPEED_LIMIT 1100 steps/s "
    "(e-puck1: 1000; Webots e-puck2: 1200)",
}

EPUCK = RobotProfile(
    name="epuck",
    wheel_radius=0.0205,
    axle_length=0.053,
    body_radius=0.037,
    max_wheel_speed=1100 * 2.0 * math.pi / 1000,  # firmware clamp MOTOR_SPEED_LIMIT = 1100 steps/s
    mass=0.13,
    has_gyro=True,
    aliases=("e-puck2",),
    sources=_PHYSICAL_SOURCES,
)
#: The physical e-puck2 (the ``epuck`` profile): the name the real-robot adapters use.
EPUCK2 = EPUCK

EPUCK1 = RobotProfile(
    name="e-puck1",
    wheel_radius=0.0205,
    axle_length=0.053,
    body_radius=0.037,
    max_wheel_speed=2.0 * math.pi,  # 1000 steps/s
    mass=0.15,
    sources={
        **_PHYSICAL_SOURCES,
        "max_wheel_speed": "1000 steps/s (e-puck.org); no gyro",
    },
)

EPUCK_VREP = RobotProfile(
    name="epuck-vrep",
    wheel_radius=0.02118,
    axle_length=0.054,
    body_radius=0.0352,
    max_wheel_speed=2.0 * math.pi,
    prox_aperture=math.radians(30.0),
    prox_model="cone",
    prox_min_distance=0.0015,
    prox_max_distance=0.0415,
    prox_poses=_VREP_PROX_POSES,
    ground_poses=_VREP_GROUND_POSES,
    camera_height=0.0277,
    camera_forward=0.0345,
    sources={
        "wheel_radius": "21.18 mm: e-puck.ttm wheel cylinder Ø 42.35 mm (decoded)",
        "axle_length": "54 mm: e-puck.ttm wheel joints at ±27 mm (decoded)",
        "body_radius": "35.2 mm: farthest corner of e-puck.ttm's collision cuboids (decoded; "
        "the university's variant 36.2 mm)",
        "prox_poses": "ePuck_proxSensor1..8 positions and headings ±15°, ±45°, ±90°, ±145° "
        "(decoded), ring 34.8-35.3 mm",
        "prox_aperture": "30° cone (decoded proximity sensor volume)",
        "prox_model": "V-REP closest-point cone: exact distance, no noise",
        "prox_min_distance": "1.5 mm: the volume's inner radius (decoded)",
        "prox_max_distance": "41.5 mm: inner radius + range 40 mm (decoded)",
        "ground_poses": "ePuck_lightSensor 29.8 mm ahead, pixels -10.3, -0.7, +10.3 mm (decoded)",
        "camera": "ePuck_camera 34.5 mm ahead, 27.7 mm high (decoded); field of view "
        "not decoded, Webots' 0.84 rad",
        "max_wheel_speed": "not in the decoded model: the e-puck1's 1000 steps/s, the robot it "
        "models (its stock script drives at 120°/s)",
    },
)

PROFILES: dict[str, RobotProfile] = {p.name: p for p in (EPUCK, EPUCK_VREP, EPUCK1)}
_ALIASES: dict[str, RobotProfile] = {a: p for p in PROFILES.values() for a in p.aliases}


def profile_names() -> tuple[str, ...]:
    """Every name :func:`get_profile` accepts: the profiles, then their aliases."""
    return (*PROFILES, *_ALIASES)


def get_profile(name: str | RobotProfile) -> RobotProfile:
    """Look a profile up by name (``"epuck"``, ``"epuck-vrep"``, ``"e-puck1"``; ``"e-puck2"``
    is the physical ``epuck``); a profile passes through."""
    if isinstance(name, RobotProfile):
        return name
    try:
        return PROFILES[name] if name in PROFILES else _ALIASES[name]
    except KeyError:
        known = ", ".join(sorted(PROFILES))
        raise ValueError(f"unknown robot profile {name!r}; known profiles: {known}") from None
