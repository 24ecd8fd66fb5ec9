"""The shipped robot profiles, every number with its source, and how to find one by name.

``epuck`` (alias ``e-puck2``) is the physical e-puck2, ``e-puck1`` the physical e-puck1
(the same geometry, 1000 steps/s, no gyro), ``epuck-vrep`` V-REP's / CoppeliaSim's stock
e-puck model, decoded from public scene files. docs/profiles.md tells them apart.
"""

from __future__ import annotations

import math

from ..errors import ProfileError
from .model import RobotProfile, SensorPose

__all__ = ["EPUCK", "EPUCK1", "EPUCK2", "EPUCK_VREP", "PROFILES", "get_profile", "profile_names"]

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
# records.VREP_ORDER spelled out: V-REP sensor k is ps (5, 6, 7, 0, ...)[k]
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

_PHYSICAL_SOURCES = {
    "wheel_radius": "20.5 mm: Webots guide and e-puck.org ('about 41 mm' diameter); "
    "spread 20-20.5 mm (Webots proto wheel 20 mm, GCtronic ROS driver 20 mm)",
    "axle_length": "53 mm: e-puck.org ('about 53 mm'), ARGoS; spread 51 (Enki) - 56.5 mm",
    "body_radius": "37 mm: Webots collision cylinder; e-puck.org mechanics: 70 mm base "
    "(35 mm, what drivers use); 7.4 cm is the Webots guide's overall size",
    "prox_poses": "Webots E-puck.proto positions and guide headings (±17°, ±46°, ±90°, ±151°); "
    "the calibration table's distances are measured from them; spread: GCtronic ROS driver "
    "±10°/±40°/±160°, ring 30-40.3 mm; Enki ±18°/±45°/±142°, ring 33-35.1 mm",
    "prox_aperture": "15°: GCtronic's per-sensor aperture (Webots proto 0.1 rad)",
    "prox_model": "rays through the Webots E-puckDistanceSensor table, calibrated on a real "
    "e-puck (puckboard.ir_response), with its relative noise; reported as the firmware's "
    "calibrated value and the distance it converts to, as on the robot",
    "prox_max_distance": "50 mm reported: a calibrated value at or below the curve's 53 at "
    "5 cm reads nothing (the table: 120 at 5 cm, 67 ambient baseline at 7 cm); = the "
    "controllers' no-detection distance",
    "ground_poses": "Webots E-puckGroundSensors: x = 30 mm, 10 mm apart",
    "ground_footprint": "2 mm: the simulator's floor model; ARGoS samples one point, Enki "
    "blurs its floor with σ = 4 mm",
    "ground_dark": "0: black reads 0, as Webots' and ARGoS' ground sensors read it; a real "
    "e-puck2 reads black tape at 0.30-0.42 of white (the plausible range)",
    "ir_gain": "1: the response table is one robot's calibration; robots and sensors differ "
    "(e-puck.org IR proximity page); measure yours with puckboard calibrate ir",
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
    ground_footprint=0.0,
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
        "ground_footprint": "0, a point sample: each value is one pixel of the decoded 16×2 "
        "vision sensor, which V-REP renders with OpenGL into a buffer of exactly that "
        "resolution, without multisampling (coppeliaSimLib frameBufferObject.cpp), so a "
        "pixel takes the colour of the surface at its centre",
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
        raise ProfileError(f"unknown robot profile {name!r}; known profiles: {known}") from None
