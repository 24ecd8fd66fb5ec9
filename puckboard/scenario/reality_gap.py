"""``--variation reality-gap``: plausible robots in plausible conditions.

``--variation plausible`` varies the robot; a controller moved to a real robot also
meets another table: other noise, another tape, obstacles of another colour, a robot
put down by hand. ``reality-gap`` keeps the plausible robots exactly as ``plausible``
draws them for the same seed (the same robot) and draws the conditions of
:mod:`.conditions` and the noise levels within the ranges of :data:`CONDITION_RANGES`,
each citing its bounds or marked *assumed* where no source gives a number, and the
control loop's timing over one of the :data:`REAL_LINKS`. Evaluating a
controller on models other than the one it was designed on is Ligot & Birattari's
pseudo-reality (Swarm Intelligence, 2019) and Jakobi's envelope of noise (Adaptive
Behavior, 1997).

Every family draws from a generator of its own, seeded ``[seed, family, CONDITION_STREAM]``:
neither the robots' draws (:func:`puckboard.profile.variation_rng`) nor the simulation's
own generator change, and one more obstacle in a scene moves no robot's placement.
Uniform draws, since the sources give spreads, not distributions. A condition the run
sets itself (``--set noise.ground=0.05``) is its definition and is kept, as a profile
keeps the numbers it sets.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Collection
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..profile.links import draw_timing, get_link
from .conditions import apply_conditions, hand_placed, with_reflectance
from .scene import CircleObstacle, Control, PolygonObstacle, Scene

__all__ = [
    "CONDITION_RANGES",
    "CONDITION_STREAM",
    "REALITY_GAP",
    "ConditionRange",
    "draw_conditions",
]

#: The variation's name, as ``--variation`` takes it.
REALITY_GAP = "reality-gap"

#: The third word of every condition generator's seed (the ASCII of "COND"), apart from
#: the robots' stream ("PROF").
CONDITION_STREAM = 0x434F4E44


@dataclass(frozen=True)
class ConditionRange:
    """A plausible interval ``[low, high]`` of one setting, ``source`` citing its bounds."""

    low: float
    high: float
    source: str


#: The ranges conditions are drawn from, by setting name (SI).
CONDITION_RANGES: dict[str, ConditionRange] = {
    "noise.wheel_speed": ConditionRange(
        0.029, 0.05,
        "0.029: Enki's ±5 % uniform wheel-speed error (σ = 5 %/√3); 0.05: ARGoS e-puck "
        "wheels noise_std_dev 0.05 (argos3-epuck epuck_wheels_default_actuator.cpp)",
    ),
    "noise.proximity": ConditionRange(
        0.017, 0.10,
        "0.017: Enki's IR ×(0.97..1.03) (σ = 3 %/√3); 0.10: assumed, twice the shipped scenes' "
        "5 %, for IR noise that grows with motor speed and a running-down battery (GCtronic's "
        "IR noise page measures it without one number)",
    ),
    "noise.ground": ConditionRange(
        0.029, 0.10,
        "0.029: ARGoS ground sensors ±0.05 uniform on 0..1 (σ = 0.05/√3); 0.10: Webots "
        "E-puckGroundSensors lookup table, σ 10 % of the reading (≈0.1 on white)",
    ),
    "surface.line_contrast": ConditionRange(
        0.5, 1.0,
        "1: matte black tape on white (the scenes' ≈0.08 against ≈0.92); 0.5: a line read "
        "at ≈500 of 1023, the Webots e-puck_line example's threshold for black on a real "
        "robot (GS_WHITE 900, black below 500); glossy dark tape 'may not appear dark to "
        "the robot's sensors' (Robot Building for Beginners, ch. 6)",
    ),
    "surface.line_width": ConditionRange(
        0.012, 0.019,
        "12 mm: ½-inch electrical tape; 19 mm: ¾-inch tape, the common electrical tape "
        "width and the UK Micromouse and Robotics Society line follower's line",
    ),
    "obstacle.ir_reflectance": ConditionRange(
        0.1, 1.0,
        "assumed: 1, a light object as the IR response table's; 0.1, a black one the "
        "e-puck's IR 'hardly detects' (epucklib, a00048.html); each obstacle on its own",
    ),
    "start.offset": ConditionRange(
        -0.01, 0.01,
        "assumed: a robot put on the line by hand, the line under its ground-sensor bar "
        "(within the 10 mm sensor spacing of Webots' E-puckGroundSensors); each robot on "
        "its own, before noise.start_jitter",
    ),
    "start.heading": ConditionRange(
        -0.1745, 0.1745,
        "assumed: ±10° by eye, a robot put down along the line by hand; each robot on its own",
    ),
}  # fmt: skip

#: The links a real robot is driven over (:data:`puckboard.profile.links.LINKS`, each
#: range with its sources): one is drawn with equal odds, then its period and latency
#: within its ranges (:func:`~puckboard.profile.links.draw_timing`), rounded to whole steps of dt.
#: The simulators' own loops (CoppeliaSim, ARGoS) are models, not a robot's reality.
REAL_LINKS = ("epuck2-wifi", "bluetooth-sercom", "usb-sercom")

# The families, in the order their generators are numbered (the second word of the seed).
_FAMILIES = ("noise", "surface", "obstacle", "start", "link")


@dataclass(frozen=True)
class DrawnConditions:
    """What one seed drew: scene-wide numbers, and one number per obstacle or robot."""

    values: dict[str, float]
    reflectance: dict[str, float]
    offset: dict[str, float]
    heading: dict[str, float]
    #: the link drawn ("" when the run set its own timing) and its control timing (s)
    link: str = ""
    timing: dict[str, float] = dataclasses.field(default_factory=dict)

    def apply(self, scene: Scene) -> Scene:
        """``scene`` in these conditions."""
        if self.timing:
            control = {k.split(".", 1)[1]: v for k, v in self.timing.items()}
            scene = dataclasses.replace(
                scene, control=dataclasses.replace(scene.control, **control)
            )
        scene = apply_conditions(
            _with_noise(scene, self.values),
            {k: v for k, v in self.values.items() if k.startswith("surface.")},
        )
        obstacles = tuple(
            with_reflectance(ob, self.reflectance[_name(ob, k)])
            if _name(ob, k) in self.reflectance
            else ob
            for k, ob in enumerate(scene.obstacles)
        )
        robots = tuple(
            hand_placed(r, self.offset.get(r.name, 0.0), self.heading.get(r.name, 0.0))
            for r in scene.robots
        )
        return dataclasses.replace(scene, obstacles=obstacles, robots=robots)

    def to_dict(self) -> dict[str, Any]:
        """The drawn conditions as ``puckboard run --json`` reports them."""
        out: dict[str, Any] = dict(self.values)
        if self.reflectance:
            out["obstacle.ir_reflectance"] = dict(self.reflectance)
        if self.offset:
            out["start.offset"] = dict(self.offset)
        if self.heading:
            out["start.heading"] = dict(self.heading)
        if self.link:
            out["control.link"] = self.link
        out.update(self.timing)
        return out


def _name(obstacle: CircleObstacle | PolygonObstacle, index: int) -> str:
    return str(obstacle.name) or f"obstacle{index + 1}"


def _with_noise(scene: Scene, values: dict[str, float]) -> Scene:
    noise = {k.split(".", 1)[1]: v for k, v in values.items() if k.startswith("noise.")}
    return (
        dataclasses.replace(scene, noise=dataclasses.replace(scene.noise, **noise))
        if noise
        else scene
    )


def _rng(seed: int, family: str) -> np.random.Generator:
    return np.random.default_rng([int(seed), _FAMILIES.index(family), CONDITION_STREAM])


def _uniform(rng: np.random.Generator, name: str) -> float:
    r = CONDITION_RANGES[name]
    return float(rng.uniform(r.low, r.high))


def draw_conditions(scene: Scene, seed: int, fixed: Collection[str] = ()) -> DrawnConditions:
    """The conditions seed ``seed`` draws for ``scene``; names in ``fixed`` (set by the
    run itself) are drawn all the same, so the others do not move, and then kept as set.
    A scene without a line draws no line, one without obstacles no reflectance."""
    values: dict[str, float] = {}
    rng = _rng(seed, "noise")
    for name in ("noise.wheel_speed", "noise.proximity", "noise.ground"):
        values[name] = _uniform(rng, name)
    rng = _rng(seed, "surface")
    for name in ("surface.line_contrast", "surface.line_width"):
        value = _uniform(rng, name)
        if scene.track is not None:
            values[name] = value
    rng = _rng(seed, "obstacle")
    reflectance = {
        _name(ob, k): _uniform(rng, "obstacle.ir_reflectance")
        for k, ob in enumerate(scene.obstacles)
    }
    rng = _rng(seed, "start")
    offset: dict[str, float] = {}
    heading: dict[str, float] = {}
    for robot in scene.robots:
        offset[robot.name] = _uniform(rng, "start.offset")
        heading[robot.name] = _uniform(rng, "start.heading")
    values = {k: v for k, v in values.items() if k not in fixed}
    if "obstacle.ir_reflectance" in fixed:
        reflectance = {}
    if "start.offset" in fixed:
        offset = {}
    if "start.heading" in fixed:
        heading = {}
    rng = _rng(seed, "link")
    link = REAL_LINKS[int(rng.integers(len(REAL_LINKS)))]
    control = Control.rounded(*draw_timing(get_link(link), rng), scene.dt)
    timing = {
        "control.period": float(control.period_for(scene.dt)),
        "control.latency": control.latency,
    }
    timing = {k: v for k, v in timing.items() if k not in fixed}
    if not timing:
        link = ""
    return DrawnConditions(values, reflectance, offset, heading, link, timing)
