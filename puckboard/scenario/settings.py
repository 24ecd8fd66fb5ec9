"""Settings: every number of a scene a run may set by name, in one table.

A setting is one number of a scene as a user names it (``--set NAME=VALUE``, a sweep's
``--set NAME=V1,V2``, ``run_episode(overrides=...)``, a transfer family, a sensitivity
point): the noise levels, the physics step and the run's length, the control loop's
timing and the conditions of :mod:`.conditions`. Each :class:`Setting` says once

* its **name**, **unit** (SI) and what it **means** (help texts, error messages);
* its **bounds**: what makes sense at all, checked wherever a value is read (the
  command line, a scene file, a sweep's plan, the Python API), so a typo (``1e9`` for a
  latency) is one line instead of a run that eats the machine's memory;
* how it is **read from a scene** (:attr:`Setting.read`: the scene's own value, ``None``
  where the scene has no such thing, a line or an obstacle);
* **who may set it** besides the run: a link's timing (:attr:`Setting.link`: a profile's
  measured ``[link]``, the link ``reality-gap`` draws, a transfer family's link) and the
  sourced range ``--variation reality-gap`` draws it from (:attr:`Setting.drawn`).

A value may carry its unit (``100ms``, ``19mm``, ``10deg``), read as every quantity is
(:mod:`puckboard.units`). Times the simulator takes in whole physics steps
(``control.*``) are checked against ``dt`` where the scene is known
(:meth:`~puckboard.scenario.scene.Control.steps`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ..profile.links import LONGEST_LINK_S
from ..units import read_quantity

if TYPE_CHECKING:
    from .scene import Scene

__all__ = [
    "CONTROL_LATENCY",
    "CONTROL_PERIOD",
    "LINE_CONTRAST",
    "LINE_WIDTH",
    "OBSTACLE_REFLECTANCE",
    "SETTINGS",
    "START_HEADING",
    "START_OFFSET",
    "ConditionRange",
    "Setting",
    "check_scene",
    "link_settings",
]


@dataclass(frozen=True)
class ConditionRange:
    """A plausible interval ``[low, high]`` of one setting, ``source`` citing its bounds."""

    low: float
    high: float
    source: str


@dataclass(frozen=True)
class Setting:
    """One setting: name, unit, meaning, bounds, how a scene holds it, who may set it.

    ``group`` says where the number lives in a :class:`~puckboard.scenario.scene.Scene`:
    ``noise`` (a field of its :class:`~puckboard.scenario.scene.Noise`), ``scene`` (a
    field of the scene), ``control`` (a field of its
    :class:`~puckboard.scenario.scene.Control`) or ``condition`` (applied by
    :func:`~puckboard.scenario.conditions.apply_conditions`); ``field`` is that field's
    name. ``absent`` names what a scene lacks when :attr:`read` gives ``None``.
    ``each`` says whether ``reality-gap`` draws it once per ``obstacle`` or ``robot``
    rather than once for the scene.
    """

    name: str
    unit: str
    meaning: str
    low: float
    high: float
    group: str
    read: Callable[[Scene], float | None]
    low_open: bool = False
    drawn: ConditionRange | None = None
    link: bool = False
    absent: str = ""
    each: str = ""

    @property
    def field(self) -> str:
        """The attribute of the scene part the setting changes (``latency``)."""
        return self.name.rpartition(".")[2]

    @property
    def help(self) -> str:
        """The meaning with the unit, as help texts list a setting."""
        return f"{self.meaning} ({self.unit_text()})" if self.unit != "1" else self.meaning

    def unit_text(self) -> str:
        return {"s": "s", "m": "m", "rad": "rad", "rad/s": "rad/s"}.get(self.unit, self.unit)

    def interval(self) -> str:
        """The bounds as an interval, ``(0, 1] s``."""
        low = "(" if self.low_open else "["
        unit = "" if self.unit == "1" else f" {self.unit}"
        return f"{low}{self.low:g}, {self.high:g}]{unit}"

    def check(self, value: Any) -> float:
        """``value`` in SI (a number, or a text with its unit: ``100ms``) within the
        bounds; else a one-line ``ValueError`` naming the setting, the value and the
        interval, the same words wherever the value came from."""
        number = read_quantity(self.name, value, self.unit)
        too_low = number <= self.low if self.low_open else number < self.low
        if too_low or number > self.high or not math.isfinite(number):
            shown = value if isinstance(value, str) else f"{value:g}"
            raise ValueError(
                f"{self.name} = {shown}: outside {self.interval()} ({self.meaning}); give a "
                "value in that interval"
            )
        return number


def _noise(field: str) -> Callable[[Scene], float | None]:
    return lambda scene: float(getattr(scene.noise, field))


def _line(field: str) -> Callable[[Scene], float | None]:
    return lambda scene: None if scene.track is None else float(getattr(scene.track, field))


def _reflectance(scene: Scene) -> float | None:
    """Every obstacle's IR reflectance when they share one; NaN when they differ."""
    values = {float(ob.ir_reflectance) for ob in scene.obstacles}
    if not values:
        return None
    return values.pop() if len(values) == 1 else math.nan


def _as_placed(scene: Scene) -> float | None:
    return 0.0  # the scene's own placement, moved by nothing


#: Why a loop's timing is bounded by a second (the bound of a profile's ``[link]`` too):
#: a bigger number is a unit mistake (ms for s), not a link.
_TIMING_BOUND = "in whole steps of dt; no e-puck's link is slower than a second"

CONTROL_PERIOD = Setting(
    "control.period", "s",
    f"how often the controllers tick and command the wheels, {_TIMING_BOUND}",
    0.0, LONGEST_LINK_S, "control", lambda scene: float(scene.control.period_for(scene.dt)),
    low_open=True, link=True,
)  # fmt: skip
CONTROL_LATENCY = Setting(
    "control.latency", "s",
    f"the loop's delay from sensing to the wheels turning, {_TIMING_BOUND}",
    0.0, LONGEST_LINK_S, "control", lambda scene: float(scene.control.latency), link=True,
)  # fmt: skip
LINE_CONTRAST = Setting(
    "surface.line_contrast", "1",
    "share (0..1) of the line's contrast with the floor that the ground sensors see "
    "(1: as its colour says)",
    0.0, 1.0, "condition", _line("contrast"), absent="line",
    drawn=ConditionRange(
        0.5, 1.0,
        "1: matte black tape on white (the scenes' ≈0.08 against ≈0.92); 0.5: a line read "
        "at ≈500 of 1023, the Webots e-puck_line example's threshold for black on a real "
        "robot (GS_WHITE 900, black below 500); glossy dark tape 'may not appear dark to "
        "the robot's sensors' (Robot Building for Beginners, ch. 6)",
    ),
)  # fmt: skip
LINE_WIDTH = Setting(
    "surface.line_width", "m", "the line's width",
    0.001, 0.2, "condition", _line("width"), absent="line",
    drawn=ConditionRange(
        0.012, 0.019,
        "12 mm: ½-inch electrical tape; 19 mm: ¾-inch tape, the common electrical tape "
        "width and the UK Micromouse and Robotics Society line follower's line",
    ),
)  # fmt: skip
OBSTACLE_REFLECTANCE = Setting(
    "obstacle.ir_reflectance", "1",
    "every obstacle's IR reflectance (0..1; 1: the IR response curve's surface, about 0.1 "
    "or less: black)",
    0.0, 1.0, "condition", _reflectance, absent="obstacle", each="obstacle",
    drawn=ConditionRange(
        0.1, 1.0,
        "assumed: 1, a light object as the IR response table's; 0.1, a black one the "
        "e-puck's IR 'hardly detects' (epucklib, a00048.html); each obstacle on its own",
    ),
)  # fmt: skip
START_OFFSET = Setting(
    "start.offset", "m", "every robot's start moved sideways to its left, as placed by hand",
    -0.1, 0.1, "condition", _as_placed, each="robot",
    drawn=ConditionRange(
        -0.01, 0.01,
        "assumed: a robot put on the line by hand, the line under its ground-sensor bar "
        "(within the 10 mm sensor spacing of Webots' E-puckGroundSensors); each robot on "
        "its own, before noise.start_jitter",
    ),
)  # fmt: skip
START_HEADING = Setting(
    "start.heading", "rad", "every robot's start heading turned counter-clockwise",
    -math.pi / 2, math.pi / 2, "condition", _as_placed, each="robot",
    drawn=ConditionRange(
        -0.1745, 0.1745,
        "assumed: ±10° by eye, a robot put down along the line by hand; each robot on its own",
    ),
)  # fmt: skip

#: Every setting by name, in the order help texts list them and ``reality-gap`` draws
#: them (within a family of draws: noise, surface, obstacle, start).
SETTINGS: dict[str, Setting] = {
    s.name: s
    for s in (
        Setting(
            "noise.wheel_speed", "1", "relative σ of each wheel's actual speed",
            0.0, 1.0, "noise", _noise("wheel_speed"),
            drawn=ConditionRange(
                0.029, 0.05,
                "0.029: Enki's ±5 % uniform wheel-speed error (σ = 5 %/√3); 0.05: ARGoS "
                "e-puck wheels noise_std_dev 0.05 (argos3-epuck "
                "epuck_wheels_default_actuator.cpp)",
            ),
        ),
        Setting(
            "noise.proximity", "1", "relative σ of the raw IR proximity values",
            0.0, 1.0, "noise", _noise("proximity"),
            drawn=ConditionRange(
                0.017, 0.10,
                "0.017: Enki's IR ×(0.97..1.03) (σ = 3 %/√3); 0.10: assumed, twice the "
                "shipped scenes' 5 %, for IR noise that grows with motor speed and a "
                "running-down battery (GCtronic's IR noise page measures it without one "
                "number)",
            ),
        ),
        Setting(
            "noise.ground", "1", "absolute σ of the 0..1 ground sensor values",
            0.0, 1.0, "noise", _noise("ground"),
            drawn=ConditionRange(
                0.029, 0.10,
                "0.029: ARGoS ground sensors ±0.05 uniform on 0..1 (σ = 0.05/√3); 0.10: "
                "Webots E-puckGroundSensors lookup table, σ 10 % of the reading (≈0.1 on "
                "white)",
            ),
        ),
        Setting(
            "noise.start_jitter", "1", "σ of the start position (m) and heading (rad)",
            0.0, 0.5, "noise", _noise("start_jitter"),
        ),
        Setting(
            "noise.gyro", "rad/s", "σ of the gyro's yaw rate",
            0.0, 1.0, "noise", _noise("gyro"),
        ),
        Setting(
            "noise.gyro_bias", "rad/s", "constant offset of the gyro's yaw rate",
            -1.0, 1.0, "noise", _noise("gyro_bias"),
        ),
        Setting(
            "dt", "s", "simulation step", 0.0, 1.0, "scene", lambda scene: scene.dt,
            low_open=True,
        ),
        Setting(
            "duration", "s", "episode length in simulated seconds",
            0.0, 1e6, "scene", lambda scene: scene.duration, low_open=True,
        ),
        LINE_CONTRAST,
        LINE_WIDTH,
        OBSTACLE_REFLECTANCE,
        START_OFFSET,
        START_HEADING,
        CONTROL_PERIOD,
        CONTROL_LATENCY,
    )
}  # fmt: skip


def link_settings(period: float, latency: float) -> dict[str, float]:
    """The settings that run a scene at this loop timing (s), as ``run_episode(overrides=
    ...)`` takes them."""
    return {CONTROL_PERIOD.name: float(period), CONTROL_LATENCY.name: float(latency)}


def check_scene(scene: Scene, *, settings: Mapping[str, Setting] = SETTINGS) -> None:
    """Refuse a scene one of whose settings lies outside its bounds, however the scene
    was built (a file, overrides, or Python): a ``ValueError`` naming the scene and the
    setting. A setting the scene does not have, or holds several values of (obstacles of
    different reflectance), is not checked here: each part checks its own."""
    for setting in settings.values():
        value = setting.read(scene)
        if value is None or math.isnan(value):
            continue
        try:
            setting.check(value)
        except ValueError as exc:
            raise ValueError(f"scene {scene.name!r}: {exc}") from None
