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
from .settings import (
    OBSTACLE_REFLECTANCE,
    SETTINGS,
    START_HEADING,
    START_OFFSET,
    ConditionRange,
    link_settings,
)

__all__ = [
    "CONDITION_RANGES",
    "CONDITION_STREAM",
    "ConditionRange",
    "DrawnConditions",
    "draw_conditions",
]

#: The third word of every condition generator's seed (the ASCII of "COND"), apart from
#: the robots' stream ("PROF").
CONDITION_STREAM = 0x434F4E44

#: The ranges conditions are drawn from, by setting name (SI), each citing its bounds:
#: the settings table's (:mod:`.settings`), where each setting says who may set it.
CONDITION_RANGES: dict[str, ConditionRange] = {
    s.name: s.drawn for s in SETTINGS.values() if s.drawn is not None
}

#: The links a real robot is driven over (:data:`puckboard.profile.links.LINKS`, each
#: range with its sources): one is drawn with equal odds, then its period and latency
#: within its ranges (:func:`~puckboard.profile.links.draw_timing`), rounded to whole
#: steps of dt. The simulators' own loops (CoppeliaSim, ARGoS) are models, not a robot's
#: reality.
REAL_LINKS = ("epuck2-wifi", "bluetooth-sercom", "usb-sercom")

# The families, in the order their generators are numbered (the second word of the seed);
# a setting's family is the first word of its name, the link's settings drawn as "link".
_FAMILIES = ("noise", "surface", "obstacle", "start", "link")
_LINK_NAME = "control.link"


@dataclass(frozen=True)
class DrawnConditions:
    """What one seed drew: scene-wide numbers, and per obstacle or robot numbers by name
    (``each[setting][obstacle or robot name]``)."""

    values: dict[str, float]
    each: dict[str, dict[str, float]]
    #: the link drawn ("" when the run set its own timing) and its control timing (s)
    link: str = ""
    timing: dict[str, float] = dataclasses.field(default_factory=dict)

    def apply(self, scene: Scene) -> Scene:
        """``scene`` in these conditions."""
        if self.timing:
            control = {SETTINGS[k].field: v for k, v in self.timing.items()}
            scene = dataclasses.replace(
                scene, control=dataclasses.replace(scene.control, **control)
            )
        scene = apply_conditions(
            _with_noise(scene, self.values),
            {k: v for k, v in self.values.items() if SETTINGS[k].group == "condition"},
        )
        reflectance = self.each.get(OBSTACLE_REFLECTANCE.name, {})
        obstacles = tuple(
            with_reflectance(ob, reflectance[_name(ob, k)]) if _name(ob, k) in reflectance else ob
            for k, ob in enumerate(scene.obstacles)
        )
        offset = self.each.get(START_OFFSET.name, {})
        heading = self.each.get(START_HEADING.name, {})
        robots = tuple(
            hand_placed(r, offset.get(r.name, 0.0), heading.get(r.name, 0.0)) for r in scene.robots
        )
        return dataclasses.replace(scene, obstacles=obstacles, robots=robots)

    def to_dict(self) -> dict[str, Any]:
        """The drawn conditions as ``puckboard run --json`` reports them."""
        out: dict[str, Any] = dict(self.values)
        out.update({name: dict(values) for name, values in self.each.items() if values})
        if self.link:
            out[_LINK_NAME] = self.link
        out.update(self.timing)
        return out


def _name(obstacle: CircleObstacle | PolygonObstacle, index: int) -> str:
    return str(obstacle.name) or f"obstacle{index + 1}"


def _with_noise(scene: Scene, values: dict[str, float]) -> Scene:
    noise = {SETTINGS[k].field: v for k, v in values.items() if SETTINGS[k].group == "noise"}
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


def _names_of(scene: Scene, each: str) -> list[str]:
    if each == "obstacle":
        return [_name(ob, k) for k, ob in enumerate(scene.obstacles)]
    return [r.name for r in scene.robots]


def draw_conditions(scene: Scene, seed: int, fixed: Collection[str] = ()) -> DrawnConditions:
    """The conditions seed ``seed`` draws for ``scene``; names in ``fixed`` (set by the
    run itself) are drawn all the same, so the others do not move, and then kept as set.
    A scene without a line draws no line, one without obstacles no reflectance."""
    values: dict[str, float] = {}
    each: dict[str, dict[str, float]] = {}
    for family in _FAMILIES[:-1]:
        rng = _rng(seed, family)
        names = [n for n in CONDITION_RANGES if n.partition(".")[0] == family]
        per = {SETTINGS[n].each for n in names}
        if per == {""}:  # once for the scene: kept where the scene has the thing
            for name in names:
                value = _uniform(rng, name)
                if SETTINGS[name].read(scene) is not None:
                    values[name] = value
            continue
        (kind,) = per  # once per obstacle or robot, each its family's settings in turn
        for name in names:
            each[name] = {}
        for thing in _names_of(scene, kind):
            for name in names:
                each[name][thing] = _uniform(rng, name)
    values = {k: v for k, v in values.items() if k not in fixed}
    each = {k: v for k, v in each.items() if k not in fixed}
    rng = _rng(seed, "link")
    link = REAL_LINKS[int(rng.integers(len(REAL_LINKS)))]
    control = Control.rounded(*draw_timing(get_link(link), rng), scene.dt)
    timing = link_settings(control.period_for(scene.dt), control.latency)
    timing = {k: v for k, v in timing.items() if k not in fixed}
    if not timing:
        link = ""
    return DrawnConditions(values, each, link, timing)
