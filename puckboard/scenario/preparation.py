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

from ..errors import SceneError
from ..profile import get_profile
from .conversion import for_seed
from .overrides import apply_scene_overrides
from .robot_profiles import link_control
from .scene import Control, Scene
from .settings import CONTROL_LATENCY, CONTROL_REPEATED, SETTINGS
from .variation import NONE, Drawn, vary

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
    #: A variation's name (:mod:`.variation`).
    variation: str = NONE.name
    #: The backend simulates the control link itself (its ``link_timing`` ability), so a
    #: profile's measured link sets the run's period and latency.
    simulates_link: bool = False
    #: The backend drives a robot (not ``simulated``): its link is the robot's own, which
    #: a profile's measured link describes; nothing to simulate.
    drives_robot: bool = False


@dataclass(frozen=True)
class PreparedScene:
    """A scene part of the way through :data:`STEPS`, and what was drawn on the way."""

    scene: Scene
    #: What the variation drew besides the robots (reality-gap's conditions; ``None``:
    #: nothing).
    conditions: Drawn | None = None


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
    """The settings a run sets itself, which a variation keeps as set: those its
    settings name (they are its definition), and the loop's timing where a robot's
    profile measured its own link (:mod:`.settings` says which settings a link sets)."""
    kept = [n for n in overrides if n in SETTINGS]
    if any(get_profile(r.profile).link is not None for r in scene.robots):
        kept += [s.name for s in SETTINGS.values() if s.link]  # the robot's own link
    return kept


def draw_variation(prepared: PreparedScene, run: RunRequest) -> PreparedScene:
    """The robots as built and what else the variation draws (reality-gap: the
    conditions), each drawn once (:func:`.variation.vary`); settings the run sets itself
    are kept. A latency drawn for a backend that cannot delay a command is refused,
    naming the variation that drew it."""
    scene = prepared.scene
    varied = vary(scene, int(run.seed), run.variation, set_by_run(scene, run.overrides))
    control = varied.scene.control
    if control.needs_link and control != scene.control and not run.simulates_link:
        raise SceneError(
            f"--variation {run.variation} drew a real link's timing: {_cannot_delay(control)}"
        )
    return PreparedScene(varied.scene, varied.conditions)


def take_link_timing(prepared: PreparedScene, run: RunRequest) -> PreparedScene:
    """The link timing a robot's profile measured (:func:`.robot_profiles.link_control`),
    one rule on every backend: a backend that simulates the link runs at it; one that
    drives the robot itself has that link already; any other simulator cannot delay a
    command, so a measured latency there is refused, as any latency is."""
    if run.drives_robot:
        return prepared
    linked = link_control(prepared.scene)
    control = linked.control
    if linked is not prepared.scene and control.needs_link and not run.simulates_link:
        names = ", ".join(dict.fromkeys(get_profile(r.profile).name for r in linked.robots))
        raise SceneError(f"the profile's [link] ({names}) gives {_cannot_delay(control)}")
    return dataclasses.replace(prepared, scene=linked)


def _cannot_delay(control: Control) -> str:
    """What a link's timing asks of the simulator that only the embedded backend does:
    one latency, or one drawn per cycle with readings repeated."""
    if control.varies:
        drawn = control.cycle_latency
        asked = (
            f"{CONTROL_LATENCY.name} drawn per cycle"
            + (f" ({drawn.describe()})" if drawn is not None else "")
            + f" and {CONTROL_REPEATED.name} = {control.repeated:.2g}"
        )
    else:
        asked = f"{CONTROL_LATENCY.name} = {control.latency:g} s"
    return (
        f"{asked}, which the embedded backend alone simulates (this backend cannot delay "
        "a command); run it with --backend embedded"
    )


#: The steps from a scene as given to the scene a run plays, in order.
STEPS: tuple[Step, ...] = (draw_track, apply_settings, draw_variation, take_link_timing)


def prepare_scene(scene: Scene, run: RunRequest) -> PreparedScene:
    """``scene`` through every step of :data:`STEPS` for ``run``."""
    prepared = PreparedScene(scene)
    for step in STEPS:
        prepared = step(prepared, run)
    return prepared
