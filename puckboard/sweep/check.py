"""Check a sweep before its first episode: what ``puckboard run`` would refuse, refused once.

An episode checks its inputs when it starts: a controller spec that names nothing, a
``--set`` value its parameter cannot take, a layer the controller does not have, more
steps than an episode may take. In a sweep every episode of that controller or parameter
value would fail the same way, each after the sweep had started and the others had run,
and the mistake would show up as a column of ``error`` episodes. :func:`check_plan` makes
those checks once, on every controller and every parameter combination of the plan,
before anything runs: the same functions the episode uses, without opening a backend.

Controllers being graded (``--controllers-dir``) are the exception: a submission that
does not import or build must not stop the others, so for them a problem is a warning
and their episodes count as ``error``.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping
from typing import Any

from .plan import SCENE_CONTROLLERS, PlanError, SweepPlan, episode_overrides

__all__ = ["check_plan"]


def check_plan(plan: SweepPlan, scene: Any, *, tolerate: Collection[str] = ()) -> list[str]:
    """Refuse, with :class:`PlanError`, a plan whose episodes would fail on their inputs.

    Every parameter combination is applied to ``scene`` (profiles, noise levels, ``dt``
    and ``duration`` within the step limit) and every controller of the plan is built,
    with each combination's ``layer.<Name>.<attr>`` values set on it. Problems of the
    controllers in ``tolerate`` are returned as warnings instead (graded submissions,
    whose episodes then count as ``error``).
    """
    from ..control.episode import check_steps
    from ..scenario.overrides import apply_scene_overrides

    combos = plan.combinations()
    for combo in combos:  # the scene's part: the same for every controller
        try:
            variant = apply_scene_overrides(scene, episode_overrides(combo))
            check_steps(variant.duration, variant.dt)
        except ValueError as exc:
            raise PlanError(f"{_describe(combo)}: {exc}") from exc
    _check_layer_names(plan, scene, tolerate)
    warnings: list[str] = []
    for spec in plan.controllers:
        problem = _controller_problem(spec, scene, combos)
        if problem is None:
            continue
        if spec not in tolerate:
            raise PlanError(problem)
        warnings.append(problem)
    return warnings


def _describe(combo: Mapping[str, Any]) -> str:
    values = ", ".join(f"{k}={v}" for k, v in sorted(combo.items()))
    return f"parameters {values}" if values else "the scene"


def _robot_specs(spec: str, scene: Any) -> dict[str, str]:
    """Each robot's controller spec in an episode of controller ``spec``."""
    return {r.name: (r.controller if spec == SCENE_CONTROLLERS else spec) for r in scene.robots}


def _check_layer_names(plan: SweepPlan, scene: Any, tolerate: Collection[str]) -> None:
    """A ``layer.<Name>.<attr>`` that no controller of the plan has is a typo in the
    parameter, whoever's controllers are swept; say so rather than blame each one."""
    from ..behaviours import load_controller

    names = sorted(n for n in plan.parameter_names if n.startswith("layer."))
    if not names:
        return
    built = []
    for spec in plan.controllers:
        for one in set(_robot_specs(spec, scene).values()):
            try:
                built.append(load_controller(one))
            except (Exception, SystemExit):
                continue  # reported by _controller_problem
    for name in names:
        _, layer_name, attr = name.split(".", 2)
        holders = []
        for controller in built:
            try:
                holders.append(controller.find(layer_name))
            except KeyError:
                continue
        if built and not holders:
            raise PlanError(
                f"parameter {name}: no controller in this sweep has a layer named {layer_name!r}"
            )
        tunable = {a for layer in holders for a in layer.parameters()}
        if holders and attr not in tunable:
            raise PlanError(
                f"parameter {name}: layer {layer_name} has no parameter {attr!r}; its "
                f"parameters: {', '.join(sorted(tunable))}"
            )


def _controller_problem(spec: str, scene: Any, combos: list[dict[str, Any]]) -> str | None:
    """Why episodes of controller ``spec`` would fail on their inputs, or None.

    Built afresh for each combination with layer or factory parameters (their values are checked
    on the layers themselves), once otherwise.
    """
    from ..behaviours import load_controller
    from ..behaviours.overrides import apply_layer_overrides, factory_keywords

    specs = _robot_specs(spec, scene)
    layered = [
        {k: v for k, v in c.items() if k.startswith(("layer.", "controller."))} for c in combos
    ]
    for layers in [p for p in layered if p] or [{}]:
        controllers = {}
        for robot, one in specs.items():
            try:
                controllers[robot] = load_controller(one, **factory_keywords(layers))
            except (Exception, SystemExit) as exc:  # its own code may raise anything
                whose = f" (robot {robot}'s, from the scene)" if spec == SCENE_CONTROLLERS else ""
                return f"controller {one!r}{whose} cannot be built: {exc}"
        try:
            apply_layer_overrides(controllers, layers)
        except ValueError as exc:
            return f"controller {spec!r}: {exc}"
    return None
