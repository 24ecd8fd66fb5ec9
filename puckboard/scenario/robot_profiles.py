"""A scene's robots and their profiles: how a scene file names them, how a scene is
written back with them, and how ``profile.*`` overrides change them.

A scene names a robot's profile as a shipped profile (``profile = "epuck"``), a profile
file relative to the scene file (``profile = "my-epuck.toml"``) or the file's form inline
(``profile = { base = "epuck", set = { prox_max_distance = 0.045 } }``); ``actual`` names
the robot's truth the same way (what ``--variation plausible`` drew). Written back
(:func:`robot_profile_data`), a changed profile is stored inline, so a scene or a
recording rebuilds the very same robots without the files it once named.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Protocol

from ..errors import ProfileError, SceneError
from ..profile import (
    RobotProfile,
    apply_overrides,
    check_path,
    get_profile,
    profile_to_data,
    resolve_profile,
)
from .scene import RobotSpec, Scene

__all__ = [
    "PROFILE_OVERRIDE_NAMES",
    "SET_SOURCE",
    "apply_profile_overrides",
    "check_control_step",
    "is_profile_override",
    "read_actual",
    "read_default_profile",
    "read_profile",
    "read_robot_profiles",
    "robot_profile_data",
    "scene_profile",
]

#: The override names this module handles (``Episode(overrides=...)``, ``--set``).
PROFILE_OVERRIDE_NAMES = ("profile.<path>", "robot.<name>.profile.<path>")
#: The source recorded for a number set with ``--set``.
SET_SOURCE = "set on the command line (--set profile.PATH=VALUE)"

_PER_ROBOT = re.compile(r"^robot\.(.+)\.profile\.(.+)$")


def scene_profile(value: Any) -> str | RobotProfile:
    """What ``--profile`` or ``robot.profile`` names, for a scene's robots: a shipped
    profile by its own name (an alias resolved), or a profile (a profile file is read).
    Errors are one-line :class:`~puckboard.errors.ProfileError`."""
    chosen = resolve_profile(value)
    return get_profile(chosen).name if isinstance(chosen, str) else chosen


def _scene_dir(source: str) -> Path | None:
    """The folder a scene file's relative profile files are in (``None``: no file)."""
    path = Path(source)
    return path.parent if path.suffix.lower() in (".toml", ".json") and path.is_file() else None


def read_profile(value: Any, *, source: str, where: str) -> str | RobotProfile:
    """A scene file's ``profile`` value: a shipped name (kept as written), a profile file
    (relative to the scene file) or the file's form inline; ``SceneError`` naming the
    scene file and the field if it is none of those."""
    try:
        return resolve_profile(value, relative_to=_scene_dir(source))
    except ProfileError as exc:
        raise SceneError(f"{source}: {where}: {exc}") from None


def read_actual(value: Any, *, source: str, where: str) -> RobotProfile:
    """A scene file's ``actual`` value (a robot's truth), as a profile."""
    return get_profile(read_profile(value, source=source, where=where))


class _Table(Protocol):
    """A table of a scene file being read (scenefile's reader): its keys and where it is."""

    source: str

    def has(self, key: str) -> bool: ...

    def raw(self, key: str) -> Any: ...

    def where(self, key: str) -> str: ...


def read_default_profile(top: _Table) -> str | RobotProfile:
    """The scene's ``profile`` (every robot's unless it names its own); ``epuck`` if none."""
    if not top.has("profile"):
        return "epuck"
    return read_profile(top.raw("profile"), source=top.source, where=top.where("profile"))


def read_robot_profiles(
    robot: _Table, default: str | RobotProfile
) -> tuple[str | RobotProfile, RobotProfile | None]:
    """A robot table's ``profile`` (else ``default``) and ``actual`` (else ``None``)."""
    profile = default
    if robot.has("profile"):
        profile = read_profile(
            robot.raw("profile"), source=robot.source, where=robot.where("profile")
        )
    actual = None
    if robot.has("actual"):
        actual = read_actual(robot.raw("actual"), source=robot.source, where=robot.where("actual"))
    return profile, actual


def robot_profile_data(robot: RobotSpec) -> dict[str, Any]:
    """The ``profile`` (and ``actual``, when there is one) entries of a robot's table."""
    out: dict[str, Any] = {"profile": profile_to_data(robot.profile)}
    if robot.actual is not None:
        out["actual"] = profile_to_data(robot.actual)
    return out


def is_profile_override(name: str) -> bool:
    """Whether ``name`` is a ``profile.<path>`` or ``robot.<name>.profile.<path>`` override."""
    return name.startswith("profile.") or _PER_ROBOT.match(name) is not None


def apply_profile_overrides(scene: Scene, overrides: Mapping[str, Any]) -> Scene:
    """``scene`` with ``profile.<path>`` set on every robot's profile and
    ``robot.<name>.profile.<path>`` on one robot's (both on the believed profile and on
    the truth, when a robot has one: a set number defines the robot). Other names are
    left alone. Errors are ``ValueError`` naming the override."""
    every: dict[str, Any] = {}
    per_robot: dict[str, dict[str, Any]] = {}
    names = [r.name for r in scene.robots]
    for name, value in overrides.items():
        match = _PER_ROBOT.match(name)
        if name.startswith("profile."):
            every[_checked(name, name[len("profile.") :])] = value
        elif match is not None:
            robot, path = match.group(1), match.group(2)
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
        return check_path(path)
    except ProfileError as exc:
        raise ProfileError(f"override {name!r}: {exc}") from None


def _changed(spec: RobotSpec, changes: Mapping[str, Any]) -> RobotSpec:
    try:
        profile = apply_overrides(get_profile(spec.profile), changes, source=SET_SOURCE)
        actual = (
            None
            if spec.actual is None
            else apply_overrides(spec.actual, changes, source=SET_SOURCE)
        )
    except ProfileError as exc:
        raise ProfileError(f"profile.{exc} (robot {spec.name!r})") from None
    return dataclasses.replace(spec, profile=profile, actual=actual)


def check_control_step(scene: Scene, dt: float) -> None:
    """Refuse a simulation step ``dt`` (s) longer than a robot's control can act on.

    Each tick the layers read the IR sensors once and command the wheels once. At its
    top speed a robot crosses its IR range in ``prox_range / (max_wheel_speed ×
    wheel_radius)`` seconds (0.35 s for the physical e-puck): a longer step lets an
    obstacle come into range and be hit between two ticks, so the run would judge the
    step, not the controller. A ``SceneError`` names the bound and that reason.
    """
    from ..profile import get_profile

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
    limit, name = min(limits)
    if dt > limit:
        shown = math.floor(limit * 100) / 100  # rounded down: a dt of the number shown passes
        raise SceneError(
            f"dt {dt:g} s is longer than the robots' control can act on: at top speed robot "
            f"{name!r} crosses its IR range in {limit:.2f} s, so an obstacle could appear and "
            f"be hit between two ticks; use dt ≤ {shown:.2f} s (the shipped scenes use 0.05)"
        )
