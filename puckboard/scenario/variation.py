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

from ..errors import ProfileError
from ..profile import VARIATIONS, draw, get_profile, variation_rng
from .reality_gap import REALITY_GAP, draw_conditions
from .scene import Scene

__all__ = ["check_variation", "vary_scene"]


def check_variation(variation: str) -> str:
    """``variation`` if it is one of :data:`~puckboard.profile.VARIATIONS`, else a one-line
    :class:`~puckboard.errors.ProfileError`."""
    if variation not in VARIATIONS:
        raise ProfileError(f"unknown variation {variation!r}; use one of {', '.join(VARIATIONS)}")
    return variation


def vary_scene(
    scene: Scene, seed: int, variation: str = "none", fixed: Collection[str] = ()
) -> Scene:
    """``scene`` with every robot's truth drawn (``plausible``), and in drawn conditions
    too (``reality-gap``: the same robots, conditions set in ``fixed`` kept), or as it
    is (``none``).

    A robot whose truth the scene already gives (a recording of a varied run, a scene
    file's ``actual``) keeps it: that is the robot the scene describes.
    """
    if check_variation(variation) == "none":
        return scene
    if variation == REALITY_GAP:
        robots_drawn = vary_scene(scene, seed, "plausible")
        return draw_conditions(scene, seed, fixed).apply(robots_drawn)
    robots = tuple(
        spec
        if spec.actual is not None
        else dataclasses.replace(
            spec, actual=draw(get_profile(spec.profile), variation_rng(seed, i))
        )
        for i, spec in enumerate(scene.robots)
    )
    return dataclasses.replace(scene, robots=robots)
