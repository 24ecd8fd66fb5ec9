"""Plausible robots for a scene: each robot's truth drawn from its profile's ranges.

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

from ..profile import draw, get_profile, variation_rng
from .scene import Scene

__all__ = ["plausible_robots"]


def plausible_robots(scene: Scene, seed: int) -> Scene:
    """``scene`` with every robot's truth drawn within its profile's plausible ranges.

    A robot whose truth the scene already gives (a recording of a varied run, a scene
    file's ``actual``) keeps it: that is the robot the scene describes.
    """
    robots = tuple(
        spec
        if spec.actual is not None
        else dataclasses.replace(
            spec, actual=draw(get_profile(spec.profile), variation_rng(seed, i))
        )
        for i, spec in enumerate(scene.robots)
    )
    return dataclasses.replace(scene, robots=robots)
