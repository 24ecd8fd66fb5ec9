"""The sweep plan: every combination of controller × parameter values × seed.

A plan is plain data, built from the command line (``--seeds A:B``, ``--set PARAM=V1,V2``)
or from Python, so that the same plan can be run on local processes or on a Dask cluster
and give the same episodes. Each episode is identified by scenario + controller + seed +
parameter values (:func:`episode_key`); that identity is what makes ``--out`` files
resumable, so it must not depend on the order in which episodes ran or where.
"""

from __future__ import annotations

import functools
import itertools
import json
import math
import re
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from ..profile.model import RobotProfile

__all__ = [
    "LABEL_PREFIX",
    "SCENE_CONTROLLERS",
    "EpisodeSpec",
    "PlanError",
    "SweepPlan",
    "check_parameter",
    "episode_key",
    "episode_overrides",
    "parameters",
    "params_key",
    "parse_seeds",
    "parse_set",
    "profile_parameters",
    "seeds_text",
]

#: Controller spec meaning "each robot keeps the controller its scene names".
SCENE_CONTROLLERS = "scene"


@functools.cache
def parameters() -> dict[str, str]:
    """Parameters ``run_episode(overrides=...)`` understands, besides
    ``layer.<Layer>.<attr>``, each with its meaning: the scene's settings
    (:mod:`puckboard.scenario.settings`) and the robots'. Read on first use: this module
    is imported before numpy may be (:mod:`puckboard.sweep.signals`)."""
    from ..scenario.settings import SETTINGS
    from ..scenario.variation import variations_help

    return {
        "robot.profile": "every robot's profile (epuck, epuck-vrep, e-puck1; see puckboard "
        "profiles)",
        **{s.name: s.help for s in SETTINGS.values()},
        "variation": variations_help(),
        "controller.<keyword>": "a keyword of the controller's factory (e.g. controller.speed)",
        "profile.<path>": "a number of every robot's profile (SI; see puckboard profiles show)",
    }


#: Names of *labels*: text that an episode's identity (its key, its row's ``params``)
#: carries and the episode itself is never given, so a study can say which of its points
#: an episode belongs to where the parameters alone cannot (``puckboard sensitivity``
#: marks its one-at-a-time points that draw the other numbers with ``label.field``).
LABEL_PREFIX = "label."

_CONTROLLER_PARAM = re.compile(r"^controller\.[A-Za-z_]\w*$")


class PlanError(ValueError):
    """A malformed sweep specification; the message says what was wrong and how to fix it."""


@dataclass(frozen=True)
class EpisodeSpec:
    """One episode to run: which controller, which seed, which parameter values.

    ``params`` is a tuple of ``(name, value)`` pairs sorted by name, so specs hash and
    compare by value and travel cheaply to worker processes.
    """

    controller: str
    seed: int
    params: tuple[tuple[str, Any], ...] = ()

    @property
    def param_dict(self) -> dict[str, Any]:
        return dict(self.params)

    def key(self, scenario: str) -> str:
        return episode_key(scenario, self.controller, self.seed, self.param_dict)


def _canonical(value: Any) -> Any:
    # 2 and 2.0 are the same setting; a resumed sweep must recognise either spelling.
    if isinstance(value, float) and math.isfinite(value) and value.is_integer():
        return int(value)
    return value


def episode_key(scenario: str, controller: str, seed: int, params: Mapping[str, Any]) -> str:
    """The identity of an episode as one canonical string (stored in the ``key`` column)."""
    canonical = {name: _canonical(params[name]) for name in sorted(params)}
    return json.dumps(
        {"scenario": scenario, "controller": controller, "seed": int(seed), "params": canonical},
        sort_keys=True,
        separators=(",", ":"),
    )


def value_key(value: Any) -> str:
    """One value as a canonical string (``2`` and ``2.0`` alike), for looking it up."""
    return json.dumps(_canonical(value))


def params_key(params: Mapping[str, Any]) -> str:
    """A parameter combination as one canonical string: equal for equal settings, however
    spelt (``2`` or ``2.0``) and whether read back from a CSV row or built in Python."""
    return json.dumps(
        {name: _canonical(params[name]) for name in sorted(params)}, separators=(",", ":")
    )


def profile_parameters(profile: str | RobotProfile) -> dict[str, Any]:
    """The episode parameters that give every robot ``profile``: a shipped profile by its
    name; a changed one (a profile file) as its base plus each value it sets and the link
    it measured (``profile.link.*``, which the episode runs at as ``run --profile`` does),
    so that every episode's identity holds the numbers it ran with and no worker needs
    the file."""
    from ..profile import get_profile
    from ..scenario.overrides import link_overrides

    if isinstance(profile, str):
        return {"robot.profile": get_profile(profile).name}
    base = profile.base or get_profile(profile).name
    out = {"robot.profile": base, **{f"profile.{p}": v for p, v in profile.overrides}}
    if profile.link is not None:
        out.update(link_overrides(profile.link))
    return out


def episode_overrides(params: Mapping[str, Any]) -> dict[str, Any]:
    """``params`` as an episode takes them: every parameter but the labels
    (:data:`LABEL_PREFIX`)."""
    return {k: v for k, v in params.items() if not k.startswith(LABEL_PREFIX)}


def check_parameter(name: str) -> str:
    """Return ``name`` if it is a parameter episodes accept (or a label), else raise
    :class:`PlanError`."""
    if name.startswith(LABEL_PREFIX) and len(name) > len(LABEL_PREFIX):
        return name
    if _is_profile_param(name):
        from ..scenario.overrides import check_profile_path

        try:
            check_profile_path(_profile_path(name))
        except ValueError as exc:
            raise PlanError(f"parameter {name}: {exc}") from None
        return name
    if (name in parameters() and "<" not in name) or _is_layer_param(name):
        return name
    if _CONTROLLER_PARAM.match(name):
        return name
    known = ", ".join(parameters())
    raise PlanError(
        f"unknown parameter {name!r}; use one of {known}, or layer.<LayerName>.<attribute> "
        "(e.g. layer.LineFollow.inner_factor)"
    )


def _is_layer_param(name: str) -> bool:
    from ..behaviours.overrides import layer_target

    try:
        return layer_target(name) is not None
    except ValueError:
        return False


def _is_profile_param(name: str) -> bool:
    from ..scenario.overrides import profile_target

    return profile_target(name) is not None


def _profile_path(name: str) -> str:
    from ..scenario.overrides import profile_target

    target = profile_target(name)
    assert target is not None
    return target[1]


def _profile_value(name: str, value: Any) -> Any:
    """A ``profile.<path>`` value in SI (``31mm`` → 0.031), checked against the path's
    bounds; other parameters' values as they are."""
    if not _is_profile_param(name):
        return value
    from ..scenario.overrides import profile_value

    try:
        return profile_value(_profile_path(name), value)
    except ValueError as exc:
        raise PlanError(f"parameter {name}: {exc}") from None


def _check_value(name: str, value: Any) -> Any:
    """``value`` as an episode of parameter ``name`` takes it (a setting in SI: ``100ms``
    → 0.1), checked; :class:`PlanError` naming the parameter otherwise."""
    if name.startswith(("layer.", "controller.", LABEL_PREFIX)):
        return value
    if _is_profile_param(name):
        return _profile_value(name, value)
    if name == "variation":
        from ..scenario.variation import check_variation

        try:
            check_variation(value)
        except ValueError as exc:
            raise PlanError(f"parameter variation: {exc}") from None
        return value
    if name == "robot.profile":
        from ..profile import profile_names

        if value not in profile_names():
            raise PlanError(
                f"parameter robot.profile: unknown profile {value!r}; "
                f"profiles: {', '.join(profile_names())}"
            )
        return value
    from ..scenario.settings import SETTINGS

    try:
        number = SETTINGS[name].check(value)
    except ValueError as exc:
        raise PlanError(f"parameter {exc}") from None
    return value if isinstance(value, (int, float)) and number == value else number


def parse_set(spec: str) -> tuple[str, tuple[Any, ...]]:
    """Parse ``PARAM=V1,V2,...`` into ``(PARAM, (v1, v2, ...))``."""
    name, sep, values_text = spec.partition("=")
    name = name.strip()
    if not sep or not name:
        raise PlanError(
            f"--set {spec!r}: expected PARAM=V1,V2,... (e.g. noise.proximity=0,0.05,0.1)"
        )
    check_parameter(name)
    parts = [p for p in (v.strip() for v in values_text.split(",")) if p]
    if not parts:
        raise PlanError(f"--set {spec!r}: no values after '='; give one or more, comma-separated")
    from ..scenario.overrides import parse_value

    values = tuple(_check_value(name, parse_value(p)) for p in parts)
    seen: set[str] = set()
    for value in values:
        canon = json.dumps(_canonical(value))
        if canon in seen:
            raise PlanError(f"--set {spec!r}: value {value!r} is listed twice")
        seen.add(canon)
    return name, values


def written_values(sets: Iterable[str]) -> dict[str, dict[str, str]]:
    """How the user wrote each value of ``--set`` specs: per parameter, the canonical
    JSON of a value (as :func:`parse_set` gives it, in SI) → its text (``12.7deg``), so
    that tables show the values the user asked for, not their SI conversion
    (``0.22165681500327983``). Specs that do not parse are left out (the plan refuses
    them with its own message)."""
    written: dict[str, dict[str, str]] = {}
    for spec in sets:
        try:
            name, values = parse_set(spec)
        except PlanError:
            continue
        parts = [p for p in (v.strip() for v in spec.partition("=")[2].split(",")) if p]
        written[name] = {value_key(v): text for v, text in zip(values, parts)}
    return written


def parse_seeds(spec: str) -> range:
    """Parse ``A:B`` (or ``A:B:STEP``) as Python's ``range(A, B[, STEP])``: A in, B out."""
    parts = spec.split(":")
    if len(parts) not in (2, 3):
        raise PlanError(
            f"--seeds {spec!r}: expected A:B, a Python range with A included and B excluded "
            "(e.g. 0:20 for seeds 0..19)"
        )
    try:
        numbers = [int(p) for p in parts]
    except ValueError:
        raise PlanError(f"--seeds {spec!r}: A, B (and STEP) must be whole numbers") from None
    if len(numbers) == 3 and numbers[2] == 0:
        raise PlanError(f"--seeds {spec!r}: STEP cannot be 0")
    seeds = range(*numbers)
    if len(seeds) == 0:
        raise PlanError(f"--seeds {spec!r} is empty; B must be greater than A (e.g. 0:10)")
    if min(seeds) < 0:
        raise PlanError(f"--seeds {spec!r}: seeds cannot be negative")
    return seeds


def seeds_text(seeds: Iterable[int]) -> str:
    """Seeds as ``--seeds`` spells them, the inverse of :func:`parse_seeds`: a range as
    ``A:B`` (``A:B:STEP``); other seeds (those read back from rows) as ``A:B`` when they
    are consecutive, else their count (``"12 seeds"``)."""
    if isinstance(seeds, range):
        step = f":{seeds.step}" if seeds.step != 1 else ""
        return f"{seeds.start}:{seeds.stop}{step}"
    s = sorted(set(seeds))
    if not s:
        return ""
    if s == list(range(s[0], s[-1] + 1)):
        return f"{s[0]}:{s[-1] + 1}"
    return f"{len(s)} seeds"


@dataclass(frozen=True)
class SweepPlan:
    """What to run: ``controllers`` × product of ``grid`` values × ``seeds``.

    ``fixed`` parameters apply to every episode (``--duration`` becomes
    ``fixed={"duration": S}``) and are part of each episode's identity, so a longer
    re-run is never mistaken for the shorter one already in the output file.

    ``points``, when given, are explicit parameter combinations, each crossed with the
    grid's product: a study that moves one parameter at a time (``puckboard
    sensitivity``) is a list of points, not a product, and runs on the same machinery.
    """

    scenario: str
    controllers: tuple[str, ...] = (SCENE_CONTROLLERS,)
    #: a range (``--seeds A:B``), or any seeds (a challenge's, drawn from its secret)
    seeds: Sequence[int] = range(10)
    grid: Mapping[str, tuple[Any, ...]] = field(default_factory=dict)
    fixed: Mapping[str, Any] = field(default_factory=dict)
    points: tuple[Mapping[str, Any], ...] = ()

    def __post_init__(self) -> None:
        if not self.controllers:
            raise PlanError("a sweep needs at least one controller")
        if len(set(self.controllers)) != len(self.controllers):
            raise PlanError(f"controller listed twice in {list(self.controllers)}")
        if len(self.seeds) == 0:
            raise PlanError("a sweep needs at least one seed")
        for name, values in self.grid.items():
            check_parameter(name)
            if not values:
                raise PlanError(f"parameter {name} has no values")
            for value in values:
                _check_value(name, value)
        for name, value in self.fixed.items():
            check_parameter(name)
            _check_value(name, value)
            if name in self.grid:
                raise PlanError(f"parameter {name} is both swept and fixed; give it once")
        self._check_points()
        object.__setattr__(self, "controllers", tuple(self.controllers))
        object.__setattr__(self, "grid", {k: tuple(v) for k, v in self.grid.items()})
        object.__setattr__(self, "fixed", dict(self.fixed))
        object.__setattr__(self, "points", tuple(dict(p) for p in self.points))

    def _check_points(self) -> None:
        seen: set[str] = set()
        for point in self.points:
            for name, value in point.items():
                check_parameter(name)
                _check_value(name, value)
                if name in self.grid or name in self.fixed:
                    raise PlanError(
                        f"parameter {name} is both in a point and swept or fixed; give it once"
                    )
            canon = json.dumps({k: _canonical(v) for k, v in point.items()}, sort_keys=True)
            if canon in seen:
                raise PlanError(f"point {canon} is listed twice")
            seen.add(canon)

    @classmethod
    def from_specs(
        cls,
        scenario: str,
        *,
        controllers: Sequence[str] = (),
        seeds: str | range = "0:10",
        sets: Iterable[str] = (),
        fixed: Mapping[str, Any] | None = None,
    ) -> SweepPlan:
        """Build a plan from command-line style strings, with errors naming the bad one."""
        grid: dict[str, tuple[Any, ...]] = {}
        for spec in sets:
            name, values = parse_set(spec)
            if name in grid:
                raise PlanError(
                    f"--set {name} given twice; list all its values once: {name}=V1,V2,..."
                )
            grid[name] = values
        seed_range = parse_seeds(seeds) if isinstance(seeds, str) else seeds
        return cls(
            scenario=scenario,
            controllers=tuple(controllers) or (SCENE_CONTROLLERS,),
            seeds=seed_range,
            grid=grid,
            fixed=dict(fixed or {}),
        )

    def combinations(self) -> list[dict[str, Any]]:
        """Every parameter combination (fixed parameters included): each point (in the
        order given) with each grid product (in grid order)."""
        names = list(self.grid)
        combos = []
        for point in self.points or ({},):
            for values in itertools.product(*(self.grid[n] for n in names)):
                combo = dict(self.fixed)
                combo.update(point)
                combo.update(zip(names, values))
                combos.append(combo)
        return combos

    @property
    def parameter_names(self) -> tuple[str, ...]:
        """Every parameter an episode of this plan may be given (grid, fixed, points)."""
        names = dict.fromkeys([*self.grid, *self.fixed, *(n for p in self.points for n in p)])
        return tuple(names)

    def episodes(self) -> Iterator[EpisodeSpec]:
        """Every episode, grouped by controller, then parameters, then seed."""
        for controller in self.controllers:
            for combo in self.combinations():
                params = tuple(sorted(combo.items()))
                for seed in self.seeds:
                    yield EpisodeSpec(controller, seed, params)

    def __len__(self) -> int:
        return len(self.controllers) * len(self.combinations()) * len(self.seeds)

    @property
    def swept(self) -> tuple[str, ...]:
        """Names of parameters that take more than one value."""
        return tuple(n for n, v in self.grid.items() if len(v) > 1)
