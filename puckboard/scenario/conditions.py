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
from .settings import (
    LINE_CONTRAST,
    LINE_WIDTH,
    OBSTACLE_REFLECTANCE,
    SETTINGS,
    START_HEADING,
    START_OFFSET,
)

__all__ = ["CONDITIONS", "apply_conditions", "hand_placed", "with_reflectance"]

#: Every condition setting with its meaning and unit (the settings table's conditions).
CONDITIONS: dict[str, str] = {s.name: s.help for s in SETTINGS.values() if s.group == "condition"}


def apply_conditions(scene: Scene, overrides: Mapping[str, Any]) -> Scene:
    """``scene`` with the condition settings among ``overrides`` applied (others are left
    alone), each checked against its bounds (a one-line ``ValueError``). A line setting on
    a scene without a track is refused: there is no line."""
    values = {}
    for name, value in overrides.items():
        if name in CONDITIONS:
            try:
                values[name] = SETTINGS[name].check(value)
            except ValueError as exc:
                raise ValueError(f"override {exc}") from None
    if not values:
        return scene
    changes: dict[str, Any] = {}
    line = {k: v for k, v in values.items() if k in (LINE_WIDTH.name, LINE_CONTRAST.name)}
    if line:
        if scene.track is None:
            raise ValueError(
                f"override {next(iter(line))}: scene {scene.name!r} has no line ([track])"
            )
        track = scene.track
        if LINE_WIDTH.name in line:
            track = dataclasses.replace(track, width=line[LINE_WIDTH.name])
        if LINE_CONTRAST.name in line:
            track = dataclasses.replace(track, contrast=line[LINE_CONTRAST.name])
        changes["track"] = track
    if OBSTACLE_REFLECTANCE.name in values:
        rho = values[OBSTACLE_REFLECTANCE.name]
        changes["obstacles"] = tuple(with_reflectance(ob, rho) for ob in scene.obstacles)
    offset = values.get(START_OFFSET.name, 0.0)
    heading = values.get(START_HEADING.name, 0.0)
    if START_OFFSET.name in values or START_HEADING.name in values:
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
