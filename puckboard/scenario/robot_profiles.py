"""A scene's robots and their profiles: how a scene file names them and how a scene is
written back with them (``profile.*`` overrides change them in :mod:`.overrides`).

A scene names a robot's profile as a shipped profile (``profile = "epuck"``), a profile
file relative to the scene file (``profile = "my-epuck.toml"``) or the file's form inline
(``profile = { base = "epuck", set = { prox_max_distance = 0.045 } }``); ``actual`` names
the robot's truth the same way (what ``--variation plausible`` drew). Written back
(:func:`robot_profile_data`), a changed profile is stored inline, so a scene or a
recording rebuilds the very same robots without the files it once named. A profile that
measured its link (``[link]``) gives the scene its loop timing (:func:`link_control`).
"""

from __future__ import annotations

import dataclasses
import logging
from pathlib import Path
from typing import Any, Protocol

from ..errors import ProfileError, SceneError
from ..profile import (
    RobotProfile,
    get_profile,
    profile_to_data,
    resolve_profile,
)
from .scene import Control, RobotSpec, Scene

__all__ = [
    "link_control",
    "read_actual",
    "read_default_profile",
    "read_profile",
    "read_robot_profiles",
    "robot_profile_data",
    "scene_profile",
]

log = logging.getLogger(__name__)


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


def link_control(scene: Scene) -> Scene:
    """``scene`` run at the link timing its robots' profiles measured (a profile file's
    ``[link]``, rounded to whole steps of ``dt``), when the scene's own loop is the
    default; a scene or ``--set control.*`` that sets the timing keeps it. Robots whose
    profiles measured different links share one loop, so that is refused in one line."""
    if scene.control != Control():
        return scene
    links = {
        link for link in (get_profile(r.profile).link for r in scene.robots) if link is not None
    }
    if not links:
        return scene
    if len(links) > 1:
        raise SceneError(
            f"scene {scene.name!r}: the robots' profiles measured different links "
            f"({', '.join(f'{p:g} s/{lat:g} s' for p, lat in sorted(links))}); one loop "
            "drives them all: set it with --set control.period=P --set control.latency=L"
        )
    ((period, latency),) = links
    dt = scene.dt
    control = Control.rounded(period, latency, dt)
    log.info(
        "running at the profile's link timing: period %.3g s, latency %.3g s (measured "
        "%.3g s and %.3g s, rounded to whole steps of %.3g s)",
        control.period, control.latency, period, latency, dt,
    )  # fmt: skip
    return dataclasses.replace(scene, control=control)
