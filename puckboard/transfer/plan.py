"""What a transfer report runs: the design model and every held-out family, per cell.

A *cell* is one controller on one profile in one scene. For each scene and profile the
plan holds one :class:`Point` per model: the design model (the scene with plausible
robots), each family's held-out point, and every scale of each family's grid. Points
with the same parameters on the same scene are one set of episodes (a noise family's
scale 1 is the design model itself, its scale 2 its held-out band), and every point runs
the same seeds (common random numbers: the same start jitter and draws at every scale,
so differences along a grid are the perturbation's, not luck's).

The episodes are ordinary sweeps (:class:`~puckboard.sweep.SweepPlan`, one per scene the
episodes run on: a family with a replacement scene adds one), run on the sweep
machinery: local cores or Dask, resumable ``--out`` rows, progress, Ctrl-C.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..scenario.overrides import link_overrides
from ..scenario.settings import SETTINGS, link_settings
from ..sweep.defaults import TRANSFER_SEEDS
from ..sweep.plan import PlanError, SweepPlan, params_key, parse_seeds, profile_parameters
from .families import DESIGN, PLAUSIBLE, Family, link_timing, scene_value

if TYPE_CHECKING:
    from ..profile import RobotProfile
    from ..scenario.scene import Scene

__all__ = [
    "DEFAULT_SEEDS",
    "Point",
    "Skipped",
    "TransferPlan",
    "family_params",
    "plan_from_names",
    "transfer_plan",
]

#: Seeds per model unless asked otherwise (:data:`puckboard.sweep.defaults.TRANSFER_SEEDS`).
DEFAULT_SEEDS = parse_seeds(TRANSFER_SEEDS)


@dataclass(frozen=True)
class Point:
    """One model for one scene and profile: the ``family`` (:data:`DESIGN` for the design
    model) at ``scale``, its episodes run on scene ``runs_on`` with ``params``."""

    scene: str
    profile: str
    family: str
    scale: float
    runs_on: str
    params: Mapping[str, Any]


@dataclass(frozen=True)
class Skipped:
    """A family not run in one scene, for one profile of it (``""``: every profile):
    ``why`` says why (it has nothing to change there, say)."""

    scene: str
    family: str
    why: str
    profile: str = ""


@dataclass(frozen=True)
class TransferPlan:
    """Every point of a report and the sweeps that run them (one per scene run on)."""

    scenes: tuple[str, ...]
    controllers: tuple[str, ...]
    profiles: Mapping[str, tuple[str, ...]]
    seeds: range
    families: tuple[Family, ...]
    points: tuple[Point, ...]
    sweeps: tuple[SweepPlan, ...]
    skipped: tuple[Skipped, ...] = ()
    fixed: Mapping[str, Any] | None = None
    #: Each scene's physics step (s): what a stepped family's scales mean there.
    dts: Mapping[str, float] | None = None

    def point_key(self, point: Point) -> str:
        """``point``'s parameters (the fixed ones included) as
        :func:`~puckboard.sweep.plan.params_key` spells them."""
        return params_key({**(self.fixed or {}), **point.params})

    def sweep_for(self, scene: str) -> SweepPlan:
        return next(s for s in self.sweeps if s.scenario == scene)

    def __len__(self) -> int:
        return sum(len(s) for s in self.sweeps)


def family_params(
    family: Family | None, scene: Scene, scale: float, base: Mapping[str, Any]
) -> dict[str, Any]:
    """The parameters of ``family`` at ``scale`` on ``scene`` (``None``: the design model),
    on top of ``base`` (the profile's). At the family's origin its scaled and stepped
    settings keep the scene's values and are left out, so that point is the design
    model's own episodes."""
    if family is None:
        return {**base, "variation": PLAUSIBLE}
    params = {**base, "variation": family.variation, **family.sets}
    if family.link is not None:
        timing = link_timing(family.link, scene.dt)
        if not measured_link(base):  # only what differs from the design loop (one step, no delay)
            design_loop = link_settings(scene.dt, 0.0)
            timing = {k: v for k, v in timing.items() if abs(v - design_loop[k]) > 1e-12}
        params.update(timing)  # a profile's own link runs wherever no timing is set
    if scale != family.origin:
        for name in family.scaled:
            value = scene_value(scene, name)
            if value:
                params[name] = value * scale
        for name in family.stepped:
            params[name] = scale * scene.dt
        for name in family.valued:
            params[name] = scale
    return params


def _same_as_design(family: Family, scene: Scene, base: Mapping[str, Any]) -> str | None:
    """Why ``family`` is the design model itself on ``scene`` (every point of it), or
    ``None`` when it changes something."""
    design = family_params(None, scene, 1.0, base)
    scales = [s for s in (family.band_scale, *family.grid) if s is not None]
    if family.scene is not None:
        if family.scene == scene.name and family.variation == PLAUSIBLE and not family.sets:
            return f"it is the design model here: {scene.name} is the scene it runs"
        return None
    if family.stepped and measured_link(base):
        return (
            "its grid starts at one step without delay, and this profile runs at the link it "
            "measured ([link])"
        )
    for name in family.valued:  # the grid's origin must be the scene's own value
        if SETTINGS[name].read(scene) is None:
            return f"{scene.name} has no {SETTINGS[name].absent}"
    for name in family.valued:
        own = scene_value(scene, name)
        if own != family.origin:
            return f"{scene.name}'s own {name} is {own:g}, not the grid's origin {family.origin:g}"
    if any(family_params(family, scene, s, base) != design for s in scales):
        return None
    if family.link is not None:
        return f"at {scene.name}'s {scene.dt * 1000:g} ms step its slow end is the design loop"
    return f"on {scene.name} it changes nothing (nothing to scale)"


def measured_link(base: Mapping[str, Any]) -> bool:
    """Whether a profile's parameters carry the link it measured (its ``[link]``)."""
    return any(name in base for name in link_overrides((0.0, 0.0)))


def transfer_plan(
    scenes: Sequence[Scene],
    *,
    controllers: Sequence[str],
    profiles: Mapping[str, Sequence[str | RobotProfile]],
    seeds: range,
    families: Sequence[Family],
    replacements: Mapping[str, Any] | None = None,
    fixed: Mapping[str, Any] | None = None,
) -> TransferPlan:
    """The points of a report on ``scenes`` (loaded scenes): for each scene and each of
    its ``profiles`` (by scene name: shipped names or profiles), the design model, then
    each family's held-out point and grid, every point for every controller on ``seeds``.

    ``replacements`` holds the loaded scene of each family's ``scene`` by name. ``fixed``
    parameters (``--duration``, ``--set``) are every model's base, each family's changes
    on top; one a family decides (:attr:`Family.changes`) is refused. Errors are
    :class:`~puckboard.sweep.PlanError`, one line each.
    """
    if not scenes:
        raise PlanError("a transfer report needs at least one scene")
    names = [s.name for s in scenes]
    if len(set(names)) != len(names):
        raise PlanError(f"scene listed twice in {names}")
    for name in fixed or {}:
        decided = [f.name for f in families if name in f.changes]
        if decided:
            raise PlanError(
                f"--set {name}: the family {decided[0]!r} decides it at its models; drop the "
                "--set, or leave that family out (--families)"
            )
    others = dict(replacements or {})
    points: list[Point] = []
    skipped: list[Skipped] = []
    labels: dict[str, tuple[str, ...]] = {}
    scenes = [_at_fixed_step(scene, fixed or {}) for scene in scenes]
    for scene in scenes:
        chosen = list(profiles.get(scene.name, ()))
        if not chosen:
            raise PlanError(f"scene {scene.name}: no profile to run")
        labels[scene.name] = tuple(_label(p) for p in chosen)
        if len(set(labels[scene.name])) != len(chosen):
            raise PlanError(f"profile listed twice in {list(labels[scene.name])}")
        for profile, label in zip(chosen, labels[scene.name]):
            base = profile_parameters(profile)
            points.append(
                Point(
                    scene.name, label, DESIGN, 1.0, scene.name, family_params(None, scene, 1, base)
                )
            )
            for family in families:
                why = _same_as_design(family, scene, base)
                if why is not None:
                    skipped.append(Skipped(scene.name, family.name, why, label))
                    continue
                runs_on = family.scene or scene.name
                if family.scene is not None and family.scene not in others:
                    raise PlanError(f"family {family.name}: scene {family.scene} is not loaded")
                scales = [s for s in (family.band_scale, *family.grid) if s is not None]
                for scale in dict.fromkeys(scales):
                    params = family_params(family, scene, scale, base)
                    points.append(Point(scene.name, label, family.name, scale, runs_on, params))
    sweeps = _sweeps(points, controllers, seeds, fixed or {})
    return TransferPlan(
        scenes=tuple(names),
        controllers=tuple(controllers),
        profiles=labels,
        seeds=seeds,
        families=tuple(families),
        points=tuple(points),
        sweeps=sweeps,
        skipped=tuple(skipped),
        fixed=dict(fixed or {}),
        dts={scene.name: float(scene.dt) for scene in scenes},
    )


def _at_fixed_step(scene: Scene, fixed: Mapping[str, Any]) -> Scene:
    """``scene`` at the physics step a fixed ``--set dt`` gives: a family whose models are
    whole steps (the loop's period and latency, a link's slow end) counts them in that
    step, so a link can be judged at a finer step than the scene's."""
    if "dt" not in fixed:
        return scene
    from ..scenario.overrides import apply_scene_overrides

    try:
        return apply_scene_overrides(scene, {"dt": fixed["dt"]})
    except ValueError as exc:
        raise PlanError(f"--set dt: {exc}") from None


def _label(profile: str | RobotProfile) -> str:
    return profile if isinstance(profile, str) else str(profile.name)


def _sweeps(
    points: Sequence[Point], controllers: Sequence[str], seeds: range, fixed: Mapping[str, Any]
) -> tuple[SweepPlan, ...]:
    """One sweep per scene run on, each set of parameters once, in the points' order."""
    by_scene: dict[str, dict[str, Mapping[str, Any]]] = {}
    for point in points:
        by_scene.setdefault(point.runs_on, {})[params_key(point.params)] = point.params
    return tuple(
        SweepPlan(
            scenario=scene,
            controllers=tuple(controllers),
            seeds=seeds,
            fixed=dict(fixed),
            points=tuple(unique.values()),
        )
        for scene, unique in by_scene.items()
    )


def plan_from_names(
    scenes: Sequence[str | Scene] | str | Scene,
    *,
    controllers: Sequence[str] = (),
    profiles: Sequence[str | RobotProfile] = (),
    seeds: range | str = DEFAULT_SEEDS,
    families: Sequence[str] | None = None,
    fixed: Mapping[str, Any] | None = None,
) -> tuple[TransferPlan, dict[str, Scene]]:
    """A report's plan from what a user names, as ``puckboard transfer`` takes it: scenes
    (shipped names, scene files or loaded scenes), controller specs (default: each
    robot's from its scene), profiles (shipped names, profile files or profiles; default:
    each scene's one), seeds (a range or ``A:B``), family names (default: all) and fixed
    parameters; and every scene its sweeps run on, loaded, by name. Checked as the
    command line checks it, before anything runs: a one-line
    :class:`~puckboard.sweep.PlanError` (or another ``ValueError``) otherwise."""
    from ..scenario.robot_profiles import scene_profile
    from ..scenario.scenefile import load_scene
    from ..sweep.check import check_plan
    from ..sweep.plan import SCENE_CONTROLLERS
    from .families import choose_families

    given = (
        [scenes] if isinstance(scenes, (str, Path)) or not isinstance(scenes, Sequence) else scenes
    )
    names = [s if isinstance(s, str) else getattr(s, "name", str(s)) for s in given]
    if len(set(names)) != len(names):
        raise PlanError(f"scene listed twice in {names}; give each once")
    chosen = choose_families(families)
    loaded = [s if not isinstance(s, (str, Path)) else load_scene(s) for s in given]
    replacements = {f.scene: load_scene(f.scene) for f in chosen if f.scene is not None}
    if profiles:
        robots = [scene_profile(p) for p in profiles]
        by_scene = {scene.name: list(robots) for scene in loaded}
    else:
        by_scene = {scene.name: [_own_profile(scene)] for scene in loaded}
    plan = transfer_plan(
        loaded,
        controllers=list(controllers) or [SCENE_CONTROLLERS],
        profiles=by_scene,
        seeds=parse_seeds(seeds) if isinstance(seeds, str) else seeds,
        families=chosen,
        replacements=replacements,
        fixed=fixed,
    )
    every = {**replacements, **{s.name: s for s in loaded}}
    for sweep in plan.sweeps:
        check_plan(sweep, every[sweep.scenario])
    return plan, every


def _own_profile(scene: Scene) -> str | RobotProfile:
    """The one profile every robot of ``scene`` has; a ``PlanError`` when they differ."""
    own = {json.dumps(_profile_id(r.profile)) for r in scene.robots}
    if len(own) != 1:
        raise PlanError(
            f"the robots of {scene.name} have different profiles; name the one to run "
            "with --profile NAME (repeatable)"
        )
    return scene.robots[0].profile


def _profile_id(profile: str | RobotProfile) -> str | list[Any]:
    return profile if isinstance(profile, str) else [profile.name, list(profile.overrides)]
