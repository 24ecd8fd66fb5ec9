"""Conditions: how the world a robot meets differs from the scene as drawn, as settings.

A scene describes its line, its obstacles and where its robots start; a classroom
table differs from it in ways no robot profile covers. Each such difference is one
setting, written like every other override (``--set NAME=VALUE``, a sweep's
``--set NAME=V1,V2``, ``run_episode(overrides=...)``), whose default is the scene as it
is, so a run without them is the run it always was:

* ``surface.line_contrast`` (0..1): the share of the line's brightness difference from
  the floor that the ground sensors (and the camera) see; 1: the line as its colour
  says; less: glossy or worn tape, a grey floor ("glossy dark materials ... may not
  appear dark to the robot's sensors", Robot Building for Beginners, ch. 6). Scene
  files: ``[track] contrast``.
* ``surface.line_width`` (m): the line's width, the scene's ``[track] width``.
* ``obstacle.ir_reflectance`` (0..1): every obstacle's IR reflectance against the
  surface the IR response curve was measured on; the e-puck's IR hardly sees black
  objects (epucklib). Scene files: each obstacle's ``ir_reflectance``.
* ``start.offset`` (m, to the robot's left) and ``start.heading`` (rad,
  counter-clockwise): every robot put down by hand that far beside and that much turned
  from where the scene places it (``noise.start_jitter`` adds its own random part on top).

:data:`CONDITIONS` names and explains them for help texts and error messages;
:func:`apply_conditions` applies those an override dict holds. ``--variation
reality-gap`` (:mod:`.reality_gap`) draws the same conditions within sourced ranges.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any

from .scene import CircleObstacle, PolygonObstacle, RobotSpec, Scene

__all__ = ["CONDITIONS", "apply_conditions", "hand_placed", "with_reflectance"]

#: Every condition setting with its unit and meaning.
CONDITIONS: dict[str, str] = {
    "surface.line_contrast": "share (0..1) of the line's contrast with the floor that the "
    "ground sensors see (1: as its colour says)",
    "surface.line_width": "the line's width (m)",
    "obstacle.ir_reflectance": "every obstacle's IR reflectance (0..1; 1: the IR response "
    "curve's surface, about 0.1 or less: black)",
    "start.offset": "every robot's start moved sideways to its left (m), as placed by hand",
    "start.heading": "every robot's start heading turned counter-clockwise (rad)",
}

#: The bounds of each setting (inclusive): contrast and reflectance are shares; a line
#: must have a width; a robot put down more than 10 cm or 90° off is not placed on the line.
_BOUNDS: dict[str, tuple[float, float]] = {
    "surface.line_contrast": (0.0, 1.0),
    "surface.line_width": (0.001, 0.2),
    "obstacle.ir_reflectance": (0.0, 1.0),
    "start.offset": (-0.1, 0.1),
    "start.heading": (-math.pi / 2, math.pi / 2),
}


def _value(name: str, value: Any) -> float:
    """``value`` as a float within the setting's bounds, else a one-line ``ValueError``."""
    low, high = _BOUNDS[name]
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ValueError(f"override {name} needs a number from {low:g} to {high:g}, got {value!r}")
    if not low <= value <= high:
        raise ValueError(
            f"override {name} must lie from {low:g} to {high:g} ({CONDITIONS[name]}), got {value!r}"
        )
    return float(value)


def apply_conditions(scene: Scene, overrides: Mapping[str, Any]) -> Scene:
    """``scene`` with the condition settings among ``overrides`` applied (others are left
    alone). A line setting on a scene without a track is refused: there is no line."""
    values = {name: _value(name, v) for name, v in overrides.items() if name in CONDITIONS}
    if not values:
        return scene
    changes: dict[str, Any] = {}
    line = {k: v for k, v in values.items() if k.startswith("surface.")}
    if line:
        if scene.track is None:
            raise ValueError(
                f"override {next(iter(line))}: scene {scene.name!r} has no line ([track])"
            )
        track = scene.track
        if "surface.line_width" in line:
            track = dataclasses.replace(track, width=line["surface.line_width"])
        if "surface.line_contrast" in line:
            track = dataclasses.replace(track, contrast=line["surface.line_contrast"])
        changes["track"] = track
    if "obstacle.ir_reflectance" in values:
        rho = values["obstacle.ir_reflectance"]
        changes["obstacles"] = tuple(with_reflectance(ob, rho) for ob in scene.obstacles)
    offset = values.get("start.offset", 0.0)
    heading = values.get("start.heading", 0.0)
    if "start.offset" in values or "start.heading" in values:
        changes["robots"] = tuple(hand_placed(r, offset, heading) for r in scene.robots)
    return dataclasses.replace(scene, **changes)


def with_reflectance(
    obstacle: CircleObstacle | PolygonObstacle, reflectance: float
) -> CircleObstacle | PolygonObstacle:
    """``obstacle`` with IR reflectance ``reflectance``."""
    return dataclasses.replace(obstacle, ir_reflectance=reflectance)


def hand_placed(robot: RobotSpec, offset: float, heading: float) -> RobotSpec:
    """``robot`` started ``offset`` m to its left and turned ``heading`` rad (wrapped)."""
    if offset == 0.0 and heading == 0.0:
        return robot
    x = robot.x - offset * math.sin(robot.theta)
    y = robot.y + offset * math.cos(robot.theta)
    theta = robot.theta + heading
    return dataclasses.replace(robot, x=x, y=y, theta=math.atan2(math.sin(theta), math.cos(theta)))
