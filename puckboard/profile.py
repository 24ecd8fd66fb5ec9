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
    "EPUCK1",
    "EPUCK2",
    "PROFILES",
    "RobotProfile",
    "SensorPose",
    "get_profile",
]


@dataclass(frozen=True)
class SensorPose:
    """Where a sensor sits on the robot: position (m) and heading (rad) in the robot frame."""

    x: float
    y: float
    heading: float


# IR proximity sensors ps0..ps7 (real e-puck order: clockwise seen from above, starting at
# the front-right sensor), at the Webots e-puck model's headings. They sit on the body's
# outline (radius 0.037 m, the collision radius): the response table's distance 0 means
# "an obstacle touching the sensor", and only at the outline can an obstacle touch it.
# (Webots' proto places them 6 mm inside its own 37 mm collision cylinder, so a touching
# wall would read 6 mm there; the sources give radii from 3.0 to 3.7 cm.)
_PROX_HEADINGS_DEG = (-17.0, -46.0, -90.0, -151.0, 151.0, 90.0, 46.0, 17.0)


def _on_outline(radius: float) -> tuple[SensorPose, ...]:
    return tuple(
        SensorPose(
            radius * math.cos(math.radians(h)), radius * math.sin(math.radians(h)), math.radians(h)
        )
        for h in _PROX_HEADINGS_DEG
    )


_PROX_POSES = _on_outline(0.037)

# Ground sensors gs0 (left), gs1 (centre), gs2 (right): 30 mm ahead of the axle, 10 mm apart.
_GROUND_POSES = (
    SensorPose(0.030, 0.010, -math.pi / 2),
    SensorPose(0.030, 0.000, -math.pi / 2),
    SensorPose(0.030, -0.010, -math.pi / 2),
)


@dataclass(frozen=True)
class RobotProfile:
    """Geometry, limits and sensor layout of one robot model.

    Attributes are SI. ``max_wheel_speed`` is the wheel's angular speed limit in rad/s;
    commands beyond it are clamped (with a warning) by every adapter.
    """

    name: str
    wheel_radius: float  # m
    axle_length: float  # m, distance between the wheels' contact points
    body_radius: float  # m, collision radius
    max_wheel_speed: float  # rad/s
    steps_per_revolution: int = 1000
    prox_range: float = 0.05  # m; nothing is reported beyond it (V-REP semantics)
    prox_aperture: float = math.radians(15.0)  # rad, full opening angle of one IR sensor
    prox_poses: tuple[SensorPose, ...] = _PROX_POSES
    ground_poses: tuple[SensorPose, ...] = _GROUND_POSES
    camera_fov: float = 0.84  # rad, horizontal field of view
    camera_height: float = 0.028  # m
    mass: float = 0.15  # kg
    has_gyro: bool = False
    extra: dict[str, float] = field(default_factory=dict, compare=False, hash=False)

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


EPUCK1 = RobotProfile(
    name="e-puck1",
    wheel_radius=0.0205,
    axle_length=0.053,
    body_radius=0.037,
    max_wheel_speed=2.0 * math.pi,  # 1000 steps/s
    mass=0.15,
)

EPUCK2 = RobotProfile(
    name="e-puck2",
    wheel_radius=0.0205,
    axle_length=0.053,
    body_radius=0.037,
    max_wheel_speed=1100 * 2.0 * math.pi / 1000,  # firmware clamp MOTOR_SPEED_LIMIT = 1100 steps/s
    mass=0.13,
    has_gyro=True,
)

PROFILES: dict[str, RobotProfile] = {p.name: p for p in (EPUCK1, EPUCK2)}


def get_profile(name: str | RobotProfile) -> RobotProfile:
    """Look a profile up by name (``"e-puck1"``, ``"e-puck2"``); a profile passes through."""
    if isinstance(name, RobotProfile):
        return name
    try:
        return PROFILES[name]
    except KeyError:
        known = ", ".join(sorted(PROFILES))
        raise ValueError(f"unknown robot profile {name!r}; known profiles: {known}") from None
