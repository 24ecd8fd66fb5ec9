"""Plausible robots for a scene: each robot's truth drawn from its profile's ranges
(and, with ``reality-gap``, plausible conditions: :mod:`.reality_gap`).

``--variation plausible`` asks how a controller fares on robots as they might really be
built, not only on the profile's numbers. Each robot of the scene gets an ``actual``
profile (:attr:`~puckboard.scenario.scene.RobotSpec.actual`) drawn by
:func:`puckboard.profile.draw` from a generator of its own, seeded ``[seed, robot index,
VARIATION_STREAM]``: the same seed draws the same robots, two robots differ, and the
simulation's own generator (noise, start jitter) draws exactly what it draws without
variation. The controller keeps believing the nominal profile.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Collection
from dataclasses import dataclass

from ..errors import ProfileError
from ..profile import VARIATIONS, draw, get_profile, variation_rng
from .reality_gap import REALITY_GAP, DrawnConditions, draw_conditions
from .scene import Scene

__all__ = ["Varied", "check_variation", "vary", "vary_scene"]


@dataclass(frozen=True)
class Varied:
    """A scene as a variation drew it, and the conditions it drew (``reality-gap``; else
    ``None``), so that what a run reports is what it ran, drawn once."""

    scene: Scene
    conditions: DrawnConditions | None = None


def check_variation(variation: str) -> str:
    """``variation`` if it is one of :data:`~puckboard.profile.VARIATIONS`, else a one-line
    :class:`~puckboard.errors.ProfileError`."""
    if variation not in VARIATIONS:
        raise ProfileError(f"unknown variation {variation!r}; use one of {', '.join(VARIATIONS)}")
    return variation


def vary_scene(
    scene: Scene, seed: int, variation: str = "none", fixed: Collection[str] = ()
) -> Scene:
    """``scene`` as :func:`vary` draws it (what it drew left unsaid)."""
    return vary(scene, seed, variation, fixed).scene


def vary(scene: Scene, seed: int, variation: str = "none", fixed: Collection[str] = ()) -> Varied:
    """``scene`` with every robot's truth drawn (``plausible``), and in drawn conditions
    too (``reality-gap``: the same robots, conditions set in ``fixed`` kept), or as it
    is (``none``); with the conditions drawn, each drawn once.

    A robot whose truth the scene already gives (a recording of a varied run, a scene
    file's ``actual``) keeps it: that is the robot the scene describes.
    """
    if check_variation(variation) == "none":
        return Varied(scene)
    if variation == REALITY_GAP:
        conditions = draw_conditions(scene, seed, fixed)
        return Varied(conditions.apply(_drawn_robots(scene, seed)), conditions)
    return Varied(_drawn_robots(scene, seed))


def _drawn_robots(scene: Scene, seed: int) -> Scene:
    """``scene`` with every robot's truth drawn from its profile's plausible ranges."""
    robots = tuple(
        spec
        if spec.actual is not None
        else dataclasses.replace(
            spec, actual=draw(get_profile(spec.profile), variation_rng(seed, i))
        )
        for i, spec in enumerate(scene.robots)
    )
    return dataclasses.replace(scene, robots=robots)
