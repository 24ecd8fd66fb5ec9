"""Overrides: a scene and its controllers changed by dotted name, without editing a file.

One dialect for every place a user writes them: ``puckboard run --set NAME=VALUE``,
``puckboard sweep --set NAME=V1,V2``, a sweep's or a sensitivity analysis's points and
``run_episode(overrides={...})``. The names:

* ``robot.profile`` (every robot's profile), ``noise.<field>``, ``dt``, ``duration``,
  ``control.period`` and ``control.latency`` (the loop's timing, whole numbers of ``dt``):
  the scene's, applied by :func:`apply_scene_overrides`;
* the conditions ``surface.line_contrast``, ``surface.line_width``,
  ``obstacle.ir_reflectance``, ``start.offset``, ``start.heading``
  (:mod:`puckboard.scenario.conditions`), applied there too;
* ``profile.<path>`` and ``robot.<name>.profile.<path>``: a number of every robot's or
  one robot's profile, by the setting names of :mod:`puckboard.profile.setting_names`
  (:func:`apply_profile_overrides`, which :func:`apply_scene_overrides` calls);
* ``layer.<LayerName>.<attribute>``: the controllers', applied by
  :func:`puckboard.behaviours.overrides.apply_layer_overrides` (a scene holds no
  controller, so they are left alone here); ``controller.<keyword>`` likewise, handed to
  the controller factory (:func:`puckboard.behaviours.overrides.factory_keywords`);
* ``variation`` (``none``, ``plausible`` or ``reality-gap``): checked here, drawn by the
  episode, which knows the seed.

A value written as text (:func:`parse_value`) is ``true``/``false``, a whole number, a
number, or else the text itself (quotes keep a number as text); a profile number may carry
its unit (``31mm``, ``17deg``), read by the setting's own check.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Iterable, Mapping
from typing import Any

from ..errors import ProfileError, SceneError
from ..profile import RobotProfile, apply_overrides, check_setting, check_value, get_profile
from ..profile.files import link_seconds
from .conditions import apply_conditions
from .robot_profiles import scene_profile
from .scene import RobotSpec, Scene
from .settings import CONTROL_PERIOD, SETTINGS
from .variation import check_variation

__all__ = [
    "LINK_PATHS",
    "OVERRIDE_NAMES",
    "SET_SOURCE",
    "apply_profile_overrides",
    "apply_scene_overrides",
    "check_control_step",
    "check_profile_path",
    "link_overrides",
    "parse_override",
    "parse_overrides",
    "parse_value",
    "profile_target",
    "profile_value",
]

OVERRIDE_NAMES = (
    "robot.profile",
    *SETTINGS,
    "layer.<LayerName>.<attribute>",
    "controller.<keyword>",
    "profile.<path>",
    "robot.<name>.profile.<path>",
    "variation",
)
"""Every name an override may have, as error messages list them."""

#: The source recorded in a profile for a number set with ``--set``.
SET_SOURCE = "set on the command line (--set profile.PATH=VALUE)"

_PER_ROBOT = re.compile(r"^robot\.(.+)\.profile\.(.+)$")


# -- text --------------------------------------------------------------------------------
def parse_value(text: str) -> bool | int | float | str:
    """``true``/``false`` → bool, then int, then float, else the string itself.

    Quote a value (``'3'`` or ``"3"``) to keep it a string.
    """
    stripped = text.strip()
    if len(stripped) >= 2 and stripped[0] == stripped[-1] and stripped[0] in "'\"":
        return stripped[1:-1]
    lowered = stripped.lower()
    if lowered in ("true", "false"):
        return lowered == "true"
    try:
        return int(stripped)
    except ValueError:
        pass
    try:
        return float(stripped)
    except ValueError:
        return stripped


def parse_override(item: str) -> tuple[str, Any]:
    """``NAME=VALUE`` as ``(NAME, value)``, the value read by :func:`parse_value`;
    ``ValueError`` (one line, with an example) when there is no ``=`` or no name.
    The name is checked where it is applied, which knows the scene and the layers."""
    name, sep, text = item.partition("=")
    name = name.strip()
    if not sep or not name:
        raise ValueError(f"--set {item!r}: expected NAME=VALUE, e.g. --set noise.wheel_speed=0.05")
    value = parse_value(text)
    if isinstance(value, float) and not math.isfinite(value):  # would reach a wheel or a sum
        raise ValueError(f"--set {item!r}: {name} must be a finite number, got {text.strip()}")
    return name, value


def parse_overrides(items: Iterable[str]) -> dict[str, Any]:
    """``NAME=VALUE`` strings (each as :func:`parse_override`) as one dict; a name given
    twice is refused (``ValueError``): which of the two was meant, only the user knows."""
    out: dict[str, Any] = {}
    for item in items:
        name, value = parse_override(item)
        if name in out:
            raise ValueError(
                f"--set {name} given twice ({name}={out[name]!r}, then {name}={value!r}); "
                "give it once"
            )
        out[name] = value
    return out


#: The paths of ``profile.link.<key>``: a profile's measured link (its ``[link]`` table),
#: so a sweep's episodes carry the link a profile file gives, as its numbers.
LINK_PATHS = ("link.period", "link.latency")


def link_overrides(link: tuple[float, float]) -> dict[str, float]:
    """The overrides that give every robot's profile the measured ``link`` (period,
    latency in s): what a profile file's ``[link]`` is among a sweep's parameters."""
    return {f"profile.{path}": float(value) for path, value in zip(LINK_PATHS, link)}


def check_profile_path(path: str) -> str:
    """``path`` of a ``profile.<path>`` override if it names something (a setting of
    :mod:`puckboard.profile.setting_names`, or the profile's ``link.period`` or
    ``link.latency``); else a one-line :class:`~puckboard.errors.ProfileError`."""
    return path.strip() if path.strip() in LINK_PATHS else check_setting(path)


def profile_value(path: str, value: Any) -> float:
    """A ``profile.<path>`` value in SI, checked: a setting's within its hard bounds, a
    link's within a link's."""
    if path.strip() in LINK_PATHS:
        return link_seconds(path.strip().partition(".")[2], value)
    return check_value(path, value)


def profile_target(name: str) -> tuple[str | None, str] | None:
    """``(robot, path)`` of a ``profile.<path>`` (robot ``None``: every robot) or
    ``robot.<name>.profile.<path>`` override; ``None`` for any other name."""
    if name.startswith("profile."):
        return None, name[len("profile.") :]
    match = _PER_ROBOT.match(name)
    return (match.group(1), match.group(2)) if match is not None else None


# -- the scene ---------------------------------------------------------------------------
def apply_scene_overrides(scene: Scene, overrides: Mapping[str, Any]) -> Scene:
    """``scene`` with the scene-level overrides applied (``robot.profile`` for every robot,
    the settings of :mod:`.settings`, ``profile.*``); ``layer.*`` and ``controller.*`` names
    are left for the controllers and ``variation`` (checked here) for the episode, which
    knows the seed. Every value is checked against its setting's bounds; unknown names and
    bad values raise a one-line ``ValueError``."""
    parts: dict[str, dict[str, Any]] = {"noise": {}, "scene": {}, "control": {}}
    for name, value in overrides.items():
        if name.startswith(("layer.", "controller.")):
            continue
        setting = SETTINGS.get(name)
        if setting is not None:
            try:
                number = setting.check(value)
            except ValueError as exc:
                raise ValueError(f"override {exc}") from None
            if setting.group in parts:  # conditions: applied below, on the scene the rest give
                parts[setting.group][setting.field] = number
        elif name == "robot.profile":
            profile = scene_profile(value)  # a clear error names the known profiles
            parts["scene"]["robots"] = scene.with_profile(profile).robots
        elif name == "variation":
            check_variation(str(value))  # drawn by the episode, which knows the seed
        elif name.startswith("noise."):
            noise = [n.partition(".")[2] for n in SETTINGS if n.startswith("noise.")]
            raise ValueError(f"unknown override {name!r}; noise fields: {', '.join(sorted(noise))}")
        elif profile_target(name) is None:
            raise ValueError(f"unknown override {name!r}; known: {', '.join(OVERRIDE_NAMES)}")
    changes = dict(parts["scene"])
    if parts["noise"]:
        changes["noise"] = dataclasses.replace(scene.noise, **parts["noise"])
    if parts["control"]:
        changes["control"] = dataclasses.replace(scene.control, **parts["control"])
    scene = dataclasses.replace(scene, **changes) if changes else scene
    scene = apply_profile_overrides(scene, overrides)  # after robot.profile: they change it
    scene = apply_conditions(scene, overrides)
    if "dt" in overrides or parts["control"]:
        try:  # the loop's timing against the step it ends with, whichever was set
            scene.control.steps(scene.dt)
        except ValueError as exc:
            raise SceneError(f"override {exc}") from None
    if "dt" in overrides or "period" in parts["control"]:
        # against the profiles the robots end with
        if scene.control.period is None:
            check_control_step(scene, scene.dt)
        else:
            check_control_step(scene, scene.control.period, name=CONTROL_PERIOD.name)
    return scene


def check_control_step(scene: Scene, dt: float, *, name: str = "dt") -> None:
    """Refuse a control step ``dt`` (s) longer than a robot's control can act on: the
    simulation step, or the control period (``name`` says which) when one is set.

    Each tick the layers read the IR sensors once and command the wheels once. At its
    top speed a robot crosses its IR range in ``prox_range / (max_wheel_speed ×
    wheel_radius)`` seconds (0.35 s for the physical e-puck): a longer step lets an
    obstacle come into range and be hit between two ticks, so the run would judge the
    step, not the controller. A ``SceneError`` names the bound and that reason.
    """
    limits = []
    for robot in scene.robots:
        profile = (
            robot.profile if isinstance(robot.profile, RobotProfile) else get_profile(robot.profile)
        )
        limits.append(
            (profile.prox_range / (profile.max_wheel_speed * profile.wheel_radius), robot.name)
        )
    if not limits:
        return
    limit, robot_name = min(limits)
    if dt > limit:
        shown = math.floor(limit * 100) / 100  # rounded down: a dt of the number shown passes
        raise SceneError(
            f"{name} {dt:g} s is longer than the robots' control can act on: at top speed robot "
            f"{robot_name!r} crosses its IR range in {limit:.2f} s, so an obstacle could appear "
            f"and be hit between two ticks; use {name} ≤ {shown:.2f} s (the shipped scenes "
            "use 0.05)"
        )


# -- the robots' profiles ----------------------------------------------------------------
def apply_profile_overrides(scene: Scene, overrides: Mapping[str, Any]) -> Scene:
    """``scene`` with ``profile.<path>`` set on every robot's profile and
    ``robot.<name>.profile.<path>`` on one robot's (both on the believed profile and on
    the truth, when a robot has one: a set number defines the robot). Other names are
    left alone. Errors are ``ValueError`` naming the override."""
    every: dict[str, Any] = {}
    per_robot: dict[str, dict[str, Any]] = {}
    names = [r.name for r in scene.robots]
    for name, value in overrides.items():
        target = profile_target(name)
        if target is None:
            continue
        robot, path = target
        if robot is None:
            every[_checked(name, path)] = value
            continue
        if robot not in names:
            raise ProfileError(
                f"override {name!r}: the scene has no robot {robot!r}; robots: {', '.join(names)}"
            )
        per_robot.setdefault(robot, {})[_checked(name, path)] = value
    if not every and not per_robot:
        return scene
    robots = []
    for spec in scene.robots:
        changes = {**every, **per_robot.get(spec.name, {})}
        robots.append(_changed(spec, changes) if changes else spec)
    return dataclasses.replace(scene, robots=tuple(robots))


def _checked(name: str, path: str) -> str:
    try:
        return check_profile_path(path)
    except ProfileError as exc:
        raise ProfileError(f"override {name!r}: {exc}") from None


def _changed(spec: RobotSpec, changes: Mapping[str, Any]) -> RobotSpec:
    numbers = {k: v for k, v in changes.items() if k not in LINK_PATHS}
    link = {k: v for k, v in changes.items() if k in LINK_PATHS}
    try:
        profile = _with_link(get_profile(spec.profile), link)
        actual = None if spec.actual is None else _with_link(spec.actual, link)
        if numbers:
            profile = apply_overrides(profile, numbers, source=SET_SOURCE)
            if actual is not None:
                actual = apply_overrides(actual, numbers, source=SET_SOURCE)
    except ProfileError as exc:
        raise ProfileError(f"profile.{exc} (robot {spec.name!r})") from None
    return dataclasses.replace(spec, profile=profile, actual=actual)


def _with_link(profile: RobotProfile, given: Mapping[str, Any]) -> RobotProfile:
    """``profile`` with its link's period and latency as ``given`` (``link.<key>``: s);
    a profile without a link needs both."""
    if not given:
        return profile
    old = dict(zip(LINK_PATHS, profile.link)) if profile.link is not None else {}
    both = {**old, **given}
    missing = [p for p in LINK_PATHS if p not in both]
    if missing:
        raise ProfileError(
            f"{missing[0]}: a link has a period and a latency, and {profile.name!r} has no "
            f"[link]; give profile.{missing[0]} too"
        )
    link = tuple(link_seconds(p.partition(".")[2], both[p]) for p in LINK_PATHS)
    return dataclasses.replace(
        profile,
        link=(link[0], link[1]),
        sources={**profile.sources, "link": SET_SOURCE},
    )
