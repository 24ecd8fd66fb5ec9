"""How sure each number of a shipped profile is: a plausible range, where its bounds come
from, and plausible robots drawn from those ranges.

A profile is one reading of sources that disagree (three drivers and simulators put the
e-puck's side IR sensors 30, 31 and 33 mm from its centre) and of robots that differ
(no two e-pucks' IR sensors answer the same wall alike). An outcome that holds only at
the shipped numbers says little about a real robot, so every outcome-shaping number
gets a :class:`Range` that cites both of its bounds, and :func:`draw` builds a plausible
robot from them: uniformly, since the sources give spreads, not distributions.

A range is never chosen by the outcome it gives. A group path (``prox_radius.side``)
carries one range for each sensor of the group, and a heading group's range is the left
sensor's (positive) heading, mirrored on the right. Numbers a profile already fixes
(``--set``, a profile file) are its definition, not an uncertainty, and are not drawn.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..records import PROX_NAMES
from .model import RobotProfile
from .setting_names import (
    PROX_GROUPS,
    apply_overrides,
    check_setting,
    concrete_settings,
    expand_setting,
    is_set,
    recorded_numbers,
    setting_value,
)

__all__ = [
    "RANGE_KINDS",
    "VARIATION_STREAM",
    "Range",
    "certainty_note",
    "draw",
    "profile_values",
    "uncertainty",
    "variation_rng",
]

#: Why a number is uncertain: the sources give different values, real robots differ from
#: each other, or the decoded variants of a simulator model differ.
RANGE_KINDS = ("sources disagree", "per robot", "decoded variants")

#: The third word of every variation generator's seed, ``[seed, robot_index, STREAM]``:
#: it names the stream (the ASCII of "PROF"), so drawing robots touches neither the
#: simulation's own generator nor any other stream seeded from the same number.
VARIATION_STREAM = 0x50524F46

#: The source of a drawn value, as :func:`draw` records it.
DRAWN = "drawn uniformly from the plausible range (--variation plausible)"


@dataclass(frozen=True)
class Range:
    """A plausible interval ``[low, high]`` (SI) for one path, ``source`` citing both
    bounds, ``kind`` one of :data:`RANGE_KINDS`."""

    low: float
    high: float
    source: str
    kind: str

    def __post_init__(self) -> None:
        if not self.low <= self.high:
            raise ValueError(f"a range needs low <= high, got {self.low}, {self.high}")
        if self.kind not in RANGE_KINDS:
            raise ValueError(f"range kind must be one of {RANGE_KINDS}, got {self.kind!r}")


def _mm(x: float, y: float) -> float:
    """Distance (m) from the robot's centre of a sensor at (x, y) mm."""
    return math.hypot(x, y) / 1000.0


_DISAGREE, _PER_ROBOT, _VARIANTS = RANGE_KINDS

# Sources, read at: Webots = cyberbotics/webots E-puck.proto and docs/guide/epuck.md;
# GCtronic = gctronic/epuck_driver_cpp src/epuck_driver_cpp.cpp (sensor TF origins and
# yaws, sensor_msgs/Range limits); Enki = enki-community/enki enki/robots/e-puck/EPuck.cpp
# (current master: the IR poses were corrected in 2013; earlier copies put ps0 at (30, -9)
# mm / 16°); ARGoS = demiurge-project/argos3-epuck epuck_entity.cpp.
_PHYSICAL: dict[str, Range] = {
    "wheel_radius.left": Range(
        0.0200, 0.0205,
        "20 mm: Webots proto wheel, GCtronic ROS driver (40 mm diameter); 20.5 mm: "
        "e-puck.org ('about 41 mm'), Webots guide",
        _DISAGREE,
    ),
    "wheel_radius.right": Range(
        0.0200, 0.0205,
        "20 mm: Webots proto wheel, GCtronic ROS driver (40 mm diameter); 20.5 mm: "
        "e-puck.org ('about 41 mm'), Webots guide",
        _DISAGREE,
    ),
    "axle_length": Range(
        0.051, 0.0565,
        "51 mm: Enki; 53 mm: e-puck.org, ARGoS, GCtronic ROS driver; 56.5 mm: a Webots "
        "teaching lab (felipenmartins/Robotics-Simulation-Labs)",
        _DISAGREE,
    ),
    "body_radius": Range(
        0.035, 0.037,
        "35 mm: e-puck.org mechanics (70 mm base), GCtronic ROS driver, ARGoS; 37 mm: Webots "
        "collision cylinder, Enki",
        _DISAGREE,
    ),
    "prox_aperture": Range(
        0.1, math.radians(15.0),
        "0.1 rad: Webots E-puckDistanceSensor aperture; 15°: GCtronic ROS driver field of "
        "view ('about 15 degrees')",
        _DISAGREE,
    ),
    "prox_max_distance": Range(
        0.040, 0.050,
        "40 mm: Webots guide (IR sensors see 'about 4 cm'); 50 mm: GCtronic ROS driver "
        "max_range",
        _DISAGREE,
    ),
    "prox_radius.front": Range(
        _mm(30, 10), _mm(35, 10),
        "31.6 mm: Webots (30, ±10) mm; Enki (33.5, ±10.5) mm = 35.1 mm; 36.4 mm: GCtronic "
        "ROS driver (35, ±10) mm",
        _DISAGREE,
    ),
    "prox_radius.diagonal": Range(
        _mm(22, 25), _mm(25, 25),
        "33.3 mm: Webots (22, ±25) mm; Enki (23, ±26) mm = 34.7 mm; 35.4 mm: GCtronic ROS "
        "driver (25, ±25) mm",
        _DISAGREE,
    ),
    "prox_radius.side": Range(
        0.030, 0.033,
        "30 mm: GCtronic ROS driver (0, ±30) mm; Webots (0, ±31) mm; 33 mm: Enki (0, ±33) mm",
        _DISAGREE,
    ),
    "prox_radius.rear": Range(
        _mm(30, 15), _mm(35, 20),
        "33.5 mm: Webots (-30, ±15) mm; Enki (-30, ±18) mm = 35.0 mm; 40.3 mm: GCtronic ROS "
        "driver (-35, ±20) mm",
        _DISAGREE,
    ),
    "prox_heading.front": Range(
        math.radians(10.0), math.radians(18.0),
        "10°: GCtronic ROS driver (yaw 0.17 rad); Webots 17°; 18°: Enki",
        _DISAGREE,
    ),
    "prox_heading.diagonal": Range(
        math.radians(40.0), math.radians(46.0),
        "40°: GCtronic ROS driver (yaw 0.70 rad); Enki 45°; 46°: Webots",
        _DISAGREE,
    ),
    "prox_heading.rear": Range(
        math.radians(142.0), math.radians(160.0),
        "142°: Enki; Webots 151°; 160°: GCtronic ROS driver (yaw 2.8 rad)",
        _DISAGREE,
    ),
    "ir_gain": Range(
        0.7, 1.3,
        "an assumed ±30 % ('tens of percent'), not a measurement: the four front sensors of "
        "one robot backing from one wall give visibly different curves, which also move "
        "with ambient light and battery (e-puck.org IR proximity page); Webots' e-puck_line "
        "subtracts offsets of 170..680 on one real robot; measure yours with puckboard "
        "calibrate ir",
        _PER_ROBOT,
    ),
    "ground_spacing": Range(
        0.009, 0.010,
        "9 mm: ARGoS (30, ±9) mm; 10 mm: Webots E-puckGroundSensors (gs0..gs2 at -10, 0, +10 mm)",
        _DISAGREE,
    ),
    "ground_footprint": Range(
        0.0, 0.004,
        "0: ARGoS samples one point; 4 mm: Enki blurs its floor with σ = 4 mm",
        _DISAGREE,
    ),
}  # fmt: skip

# V-REP's model is one exact decoded file, so its ranges are only where decoded variants
# of it differ (the V-REP e-puck model reference): the four public scene files agree to
# 0.1 mm on every sensor (one user moved one sensor in one scene: an edit, not a variant).
_VREP: dict[str, Range] = {
    "body_radius": Range(
        0.0352,
        0.0362,
        "35.2 mm: the stock e-puck.ttm (faroub/VREPSimEPuck, clement-moulin-frier/pyvrep_epuck "
        "scenes); 36.2 mm: the university's variant (pgr3931/EPuck_CoppeliaSim_1_6 "
        "basicReactiveWS19.ttt)",
        _VARIANTS,
    ),
}

# Why a shown number has no range: every source agrees, or none measures a spread.
_PHYSICAL_CERTAIN = {
    "wheel_radius": "nominal: what the robot's conversions and odometry believe; each wheel's "
    "true radius has its range",
    "max_wheel_speed": "the firmware's own clamp (e-puck2 MOTOR_SPEED_LIMIT 1100 steps/s, "
    "e-puck1 1000): no disagreement",
    "prox_min_distance": "the response table starts at 0 mm",
    "prox_heading.side": "90° in Webots, Enki and the GCtronic ROS driver",
    "ir_offset": "what the start-up calibration leaves over: no source measures it; measure "
    "yours with puckboard calibrate ir",
    "ground_forward": "30 mm in Webots and ARGoS",
}
_VREP_CERTAIN = {
    "": "decoded: the four public scene files agree to 0.1 mm",
    "max_wheel_speed": "not in the decoded model: the e-puck1's 1000 steps/s",
    "prox_max_distance": "decoded: inner radius + range; the stock script scales its "
    "no-detection distance with the model's size factor, but none of the four public scene "
    "files rescales the model",
    "ir_gain": "a cone sensor reports exact distances: no response to scale",
    "ir_offset": "a cone sensor reports exact distances: no calibration to leave over",
    "ground_footprint": "decoded: each ground value is one pixel of a 16×2 image that V-REP "
    "renders without multisampling, the colour at the pixel's centre",
}
_CERTAIN = {"epuck": _PHYSICAL_CERTAIN, "e-puck1": _PHYSICAL_CERTAIN, "epuck-vrep": _VREP_CERTAIN}

_RANGES: dict[str, dict[str, Range]] = {
    "epuck": _PHYSICAL,
    "e-puck1": _PHYSICAL,
    "epuck-vrep": _VREP,
}
for _table in _RANGES.values():
    for _path in _table:
        check_setting(_path)


def uncertainty(profile: RobotProfile) -> dict[str, Range]:
    """Every uncertain path of ``profile`` (of the shipped profile it derives from) with its
    plausible :class:`Range`; ``{}`` for a profile that derives from none."""
    return dict(_RANGES.get(profile.base or profile.name, {}))


def certainty_note(profile: RobotProfile, path: str) -> str:
    """Why ``path`` of ``profile`` has no range (``""`` when nothing is said)."""
    notes = _CERTAIN.get(profile.base or profile.name, {})
    return notes.get(path, notes.get("", ""))


def _sensor_paths(path: str) -> list[tuple[str, bool]]:
    """(single-number path, mirrored?) for each number ``path``'s range applies to."""
    head, _, group = path.partition(".")
    if head == "prox_heading" and group in PROX_GROUPS:
        left, right = PROX_GROUPS[group]
        return [(f"{head}.{PROX_NAMES[right]}", True), (f"{head}.{PROX_NAMES[left]}", False)]
    return [(p, False) for p in expand_setting(path)]


def profile_values(profile: RobotProfile) -> dict[str, float]:
    """The value of every uncertain or overridden number of ``profile``, one path per number
    (``prox_radius.right``, not ``.side``): what reports list, so that any run can be
    repeated with ``--set profile.PATH=VALUE``."""
    paths: list[str] = []
    for path in [*uncertainty(profile), *(p for p, _ in profile.overrides)]:
        for single, _ in _sensor_paths(path):
            if single not in paths:
                paths.append(single)
    order = {p: i for i, p in enumerate(concrete_settings())}
    paths.sort(key=lambda p: order.get(p, len(order)))
    # a number set by hand or drawn is reported as it was given, so that setting it again
    # rebuilds the very same robot (a radius read back from a moved pose may differ in
    # its last digit)
    given = recorded_numbers(profile)
    out: dict[str, float] = {}
    for path in paths:
        value = given.get(path)
        out[path] = setting_value(profile, path) if value is None else value
    return out


def draw(profile: RobotProfile, rng: np.random.Generator) -> RobotProfile:
    """A plausible robot: every uncertain number of ``profile`` drawn uniformly from its
    range, each sensor and wheel on its own; numbers the profile fixes are kept.

    The draws come from ``rng`` in a fixed order, so one generator state gives one robot.
    """
    drawn: dict[str, float] = {}
    for path, rng_of_path in uncertainty(profile).items():
        for single, mirrored in _sensor_paths(path):
            value = float(rng.uniform(rng_of_path.low, rng_of_path.high))
            if not is_set(profile, single):
                drawn[single] = -value if mirrored else value
    return apply_overrides(profile, drawn, source=DRAWN) if drawn else profile


def variation_rng(seed: int, robot_index: int) -> np.random.Generator:
    """The generator that draws robot ``robot_index`` of a run seeded ``seed``."""
    return np.random.default_rng([int(seed), int(robot_index), VARIATION_STREAM])
