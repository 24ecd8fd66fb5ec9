"""The robot model as one frozen record: geometry, limits, sensor layout, unit conversions.

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

__all__ = ["NO_DETECTION_DISTANCE", "RobotProfile", "SensorPose"]


@dataclass(frozen=True)
class SensorPose:
    """Where a sensor sits on the robot: position (m) and heading (rad) in the robot frame."""

    x: float
    y: float
    heading: float


# -- the physical e-puck's layout (the record's defaults) ------------------------------------
# IR proximity sensors ps0..ps7 (real e-puck order: clockwise seen from above, starting at
# the front-right sensor) at the Webots e-puck model's positions and headings (Webots
# guide "Devices orientations", E-puck.proto). Why Webots: the distance→value table that
# turns a distance into a raw reading (puckboard.ir_response) is Webots' calibration, and
# its distances are measured from these positions, so table and positions go together.
# How far the other sources lie is puckboard.profile.uncertainty's business.
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

#: The distance (m) a proximity reading takes when nothing is detected: the controllers'
#: ``noDetectionDistance`` (V-REP's stock script and the thesis's Code 4.13). A convention
#: of the readings, not a property of any sensor (V-REP's detect up to 41.5 mm).
NO_DETECTION_DISTANCE = 0.05

#: Half-width (m) of a ground sensor's light spot unless a profile says otherwise: the
#: value the simulator's floor model used before profiles carried it (sim.floor).
_GROUND_FOOTPRINT = 0.002

_UNIT_GAINS = (1.0,) * 8
_NO_OFFSETS = (0.0,) * 8


@dataclass(frozen=True)
class RobotProfile:
    """Geometry, limits and sensor layout of one robot model.

    Attributes are SI. ``max_wheel_speed`` is the wheel's angular speed limit in rad/s;
    commands beyond it are clamped (with a warning) by every adapter.

    The proximity sensors follow ``prox_model``, the name of an IR sensor model of the
    engine's registry (:mod:`puckboard.sim.ir_models`, which refuses a name it does not
    know when a world is built): ``"rays"`` (the physical robot: a fan of rays over
    ``prox_aperture`` through the calibrated response table, with noise) or ``"cone"``
    (V-REP's proximity sensor: the exact distance to the nearest point of any object
    inside a cone of ``prox_aperture``, detected only between ``prox_min_distance`` and
    ``prox_max_distance``, no noise). Either way a reading of nothing is ``prox_range``,
    the controllers' no-detection distance.

    Per robot, as built: ``ir_gain`` multiplies each IR sensor's response above its
    ambient baseline and ``ir_offset`` (raw units) is what its start-up calibration left
    over (ps0..ps7); ``wheel_radius_left``/``_right`` are the wheels' true radii (``None``:
    the nominal ``wheel_radius``, which every unit conversion uses because that is what
    the robot's software believes); ``ground_footprint`` is the half-width of a ground
    sensor's light spot.

    ``link``, when a profile file measured it (its ``[link]`` table, ``puckboard calibrate
    link``), is the (period, latency) in seconds of the link this robot is driven over;
    a run with this profile then ticks at that timing (rounded to whole simulation
    steps) unless the scene or ``--set control.*`` says otherwise.

    ``sources`` says where each number comes from (``puckboard profiles``). A profile
    changed by :func:`puckboard.profile.apply_overrides` keeps the ``name`` it was given,
    names the shipped profile it derives from in ``base`` and remembers every change in
    ``overrides`` (path, value), so it can be written down and rebuilt exactly.
    """

    name: str
    wheel_radius: float  # m, nominal
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
    ir_gain: tuple[float, ...] = _UNIT_GAINS  # 1, per IR sensor ps0..ps7
    ir_offset: tuple[float, ...] = _NO_OFFSETS  # raw units, per IR sensor ps0..ps7
    wheel_radius_left: float | None = None  # m, true radius; None = wheel_radius
    wheel_radius_right: float | None = None  # m, true radius; None = wheel_radius
    ground_footprint: float = _GROUND_FOOTPRINT  # m, half-width of a ground sensor's spot
    base: str = ""  # the shipped profile this one derives from ("": none)
    overrides: tuple[tuple[str, float], ...] = ()  # (path, value) changes from ``base``
    link: tuple[float, float] | None = None  # s, (period, latency) measured on its link
    sources: dict[str, str] = field(default_factory=dict, compare=False, hash=False)
    extra: dict[str, float] = field(default_factory=dict, compare=False, hash=False)

    def __post_init__(self) -> None:
        if not self.prox_model:
            raise ValueError("prox_model must name an IR sensor model (puckboard.sim.ir_models)")
        if not 0.0 <= self.prox_min_distance < self.prox_max_distance <= self.prox_range:
            raise ValueError(
                "need 0 <= prox_min_distance < prox_max_distance <= prox_range, got "
                f"{self.prox_min_distance}, {self.prox_max_distance}, {self.prox_range}"
            )
        for name in ("ir_gain", "ir_offset"):
            values = getattr(self, name)
            if len(values) != len(self.prox_poses):
                raise ValueError(
                    f"{name} needs one value per IR sensor ({len(self.prox_poses)}), "
                    f"got {len(values)}"
                )
            object.__setattr__(self, name, tuple(float(v) for v in values))

    # -- the wheels as built -----------------------------------------------------------
    @property
    def wheel_radii(self) -> tuple[float, float]:
        """The true (left, right) wheel radii (m): what the wheels roll, not what is believed."""
        left = self.wheel_radius if self.wheel_radius_left is None else self.wheel_radius_left
        right = self.wheel_radius if self.wheel_radius_right is None else self.wheel_radius_right
        return left, right

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
