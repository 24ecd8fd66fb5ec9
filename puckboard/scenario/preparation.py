"""The scene a run plays: the scene as given, through one pipeline of named steps.

A run does not play a scene file as written. A generated scene draws its track from the
run's seed; the run's own settings (``--set``) change it; a variation draws the robots as
built and, with ``reality-gap``, the conditions; a backend that simulates the control link
runs it at the link timing a robot's profile measured. Each of those is one step here,
in :data:`STEPS`, in the order a run takes them: a step reads the scene the one before
it made and the run's :class:`RunRequest`, and gives the next its scene and what it drew.
Every condition is drawn once, by the step that draws it, from its own seeded stream, and
that drawing is the one the run both plays and reports. Nothing here opens a backend or
builds a controller; what a backend does to the scene once it is open (driving fewer
robots, or the robot it really is) is the episode's.

A step to add (another way a run may differ from its file) is one function of this
shape, put in :data:`STEPS` where it belongs.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from ..profile import get_profile
from .conditions import CONDITIONS
from .conversion import for_seed
from .overrides import apply_scene_overrides
from .reality_gap import DrawnConditions
from .robot_profiles import link_control
from .scene import Scene
from .variation import vary

__all__ = [
    "STEPS",
    "PreparedScene",
    "RunRequest",
    "apply_settings",
    "draw_track",
    "draw_variation",
    "prepare_scene",
    "set_by_run",
    "take_link_timing",
]


@dataclass(frozen=True)
class RunRequest:
    """What a run asks of its scene, beyond the scene itself."""

    #: The run's seed: a generated track, the robots' and the conditions' draws.
    seed: int = 0
    #: The run's settings by dotted name (``--set``; ``variation`` is taken apart).
    overrides: Mapping[str, Any] = field(default_factory=dict)
    #: ``none``, ``plausible`` or ``reality-gap``.
    variation: str = "none"
    #: The backend simulates the control link itself (its ``link_timing`` ability), so a
    #: profile's measured link sets the run's period and latency.
    simulates_link: bool = False


@dataclass(frozen=True)
class PreparedScene:
    """A scene part of the way through :data:`STEPS`, and what was drawn on the way."""

    scene: Scene
    #: The conditions ``reality-gap`` drew (``None``: no such variation).
    conditions: DrawnConditions | None = None


Step = Callable[[PreparedScene, RunRequest], PreparedScene]


def draw_track(prepared: PreparedScene, run: RunRequest) -> PreparedScene:
    """A generated scene's track, drawn from the run's seed (any other scene as it is)."""
    return dataclasses.replace(prepared, scene=for_seed(prepared.scene, int(run.seed)))


def apply_settings(prepared: PreparedScene, run: RunRequest) -> PreparedScene:
    """The run's own settings, by dotted name (:mod:`.overrides`)."""
    return dataclasses.replace(
        prepared, scene=apply_scene_overrides(prepared.scene, run.overrides)
    )


def set_by_run(scene: Scene, overrides: Mapping[str, Any]) -> list[str]:
    """The conditions a run sets itself, which a variation keeps as set: those its
    settings name (they are its definition), and the loop's timing where a robot's
    profile measured its own link."""
    kept = [n for n in overrides if n in CONDITIONS or n.startswith(("noise.", "control."))]
    if any(get_profile(r.profile).link is not None for r in scene.robots):
        kept += ["control.period", "control.latency"]  # the robot's own, measured link
    return kept


def draw_variation(prepared: PreparedScene, run: RunRequest) -> PreparedScene:
    """The robots as built and, with ``reality-gap``, the conditions, each drawn once
    (:func:`.variation.vary`); conditions the run sets itself are kept."""
    scene = prepared.scene
    varied = vary(scene, int(run.seed), run.variation, set_by_run(scene, run.overrides))
    return PreparedScene(varied.scene, varied.conditions)


def take_link_timing(prepared: PreparedScene, run: RunRequest) -> PreparedScene:
    """On a backend that simulates the link, the link timing a robot's profile measured
    (:func:`.robot_profiles.link_control`); elsewhere the link is its own."""
    if not run.simulates_link:
        return prepared
    return dataclasses.replace(prepared, scene=link_control(prepared.scene))


#: The steps from a scene as given to the scene a run plays, in order.
STEPS: tuple[Step, ...] = (draw_track, apply_settings, draw_variation, take_link_timing)


def prepare_scene(scene: Scene, run: RunRequest) -> PreparedScene:
    """``scene`` through every step of :data:`STEPS` for ``run``."""
    prepared = PreparedScene(scene)
    for step in STEPS:
        prepared = step(prepared, run)
    return prepared
