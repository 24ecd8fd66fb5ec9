"""The joint method: robots drawn with every number at once, the band and its causes from
the same episodes.

Each seed of ``--variation plausible`` draws every uncertain number of every robot within
its range (:func:`puckboard.profile.draw`), and each episode's row carries what was
drawn (``robot.NAME.profile_values``). So one set of episodes per controller × profile is
at once the band (the plausible robots' pass rate) and a sample of the whole space of
numbers, from which :mod:`.estimate` bins a curve per number and ranks the numbers.

**Attribution.** An episode's outcome depends on both robots, and each robot draws its
~30 numbers on its own. A number is attributed *per robot*: ``left: body_radius`` and
``right: body_radius`` are two inputs. The robots of a scene play different parts (in the
two-robot pass they go round the loop in opposite directions, so what one meets on its
right the other meets on its left) and a number can matter for one part only; the two
robots' mean would halve such an effect and mix it with noise from the other robot, and
"the robot that failed" is not defined for an episode that passes and selects on the
outcome for one that fails. A number that matters for both robots shows up twice, each
with part of its effect.

The rows are those of the one-at-a-time method's plausible point (same parameters, same
keys), so either method's ``--out`` file feeds the other, and :func:`from_rows` recomputes
an analysis from a file without running an episode.
"""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ...profile import apply_overrides, get_profile, profile_values
from ...sweep.options import DEFAULT_RUN, RunOptions
from ...sweep.plan import PlanError, SweepPlan, params_key, profile_parameters, seeds_text
from ...sweep.rows import Outcome
from ...sweep.run import SweepResult
from ...sweep.summary import GroupSummary
from ..one_at_a_time.plan import FIELD_LABEL, PLAUSIBLE
from .estimate import (
    DEFAULT_BINS,
    PASS,
    PROGRESS,
    Bin,
    Effect,
    Interaction,
    binned_curve,
    main_effect,
    ranking_outcome,
    strongest_interaction,
)

if TYPE_CHECKING:
    from pathlib import Path

    from ...profile import RobotProfile
    from ...scenario.scene import Scene

__all__ = [
    "JointAnalysis",
    "JointPlan",
    "JointResult",
    "Number",
    "analyse_rows",
    "from_rows",
    "joint_plan",
    "profile_label",
    "run_joint",
    "verdict",
]

_PROFILE_VALUES = ".profile_values"


@dataclass(frozen=True)
class JointPlan:
    """One plausible point per profile for every controller of ``sweep``."""

    sweep: SweepPlan
    profiles: tuple[str, ...]
    bins: int = DEFAULT_BINS

    @property
    def scenario(self) -> str:
        return self.sweep.scenario

    def __len__(self) -> int:
        return len(self.sweep)


def joint_plan(
    scenario: str,
    *,
    profiles: Sequence[str | RobotProfile],
    controllers: Sequence[str],
    seeds: range,
    fixed: Mapping[str, Any] | None = None,
    bins: int = DEFAULT_BINS,
) -> JointPlan:
    """Plausible robots of each of ``profiles`` (names or profiles) on ``seeds``."""
    if bins < 2:
        raise PlanError(f"--bins must be at least 2, got {bins}")
    if len(seeds) < 2 * bins:
        raise PlanError(
            f"--seeds {seeds.start}:{seeds.stop} gives {len(seeds)} episodes, too few for "
            f"{bins} bins; the joint method wants hundreds (e.g. --seeds 0:300)"
        )
    chosen = [get_profile(p) for p in profiles]
    if not chosen:
        raise PlanError("a sensitivity analysis needs at least one profile")
    labels = [p.name for p in chosen]
    if len(set(labels)) != len(labels):
        raise PlanError(f"profile listed twice in {labels}")
    points = tuple({**profile_parameters(p), "variation": PLAUSIBLE} for p in chosen)
    sweep = SweepPlan(
        scenario=scenario,
        controllers=tuple(controllers),
        seeds=seeds,
        fixed=dict(fixed or {}),
        points=points,
    )
    return JointPlan(sweep, tuple(labels), bins)


@dataclass(frozen=True)
class Number:
    """One drawn number of one robot: its curve and its index on both outcomes."""

    robot: str
    path: str
    shipped: float | None
    bins: tuple[Bin, ...]
    effects: Mapping[str, Effect | None]

    @property
    def name(self) -> str:
        return f"{self.robot}: {self.path}"

    def effect(self, outcome: str) -> Effect | None:
        return self.effects.get(outcome)

    def to_dict(self) -> dict[str, Any]:
        return {
            "number": self.name,
            "robot": self.robot,
            "path": self.path,
            "shipped_value": self.shipped,
            "index": {k: None if e is None else e.to_dict() for k, e in self.effects.items()},
            "bins": [b.to_dict() for b in self.bins],
        }


@dataclass(frozen=True)
class JointAnalysis:
    """One controller on one profile: the band, every number, the ranking."""

    controller: str
    profile: str
    params: Mapping[str, Any]
    band: GroupSummary
    numbers: tuple[Number, ...]
    ranked_by: str
    interaction: Interaction | None

    def _strength(self, n: Number) -> float:
        e = n.effect(self.ranked_by)
        return 0.0 if e is None else abs(e.z)

    @property
    def ranking(self) -> list[Number]:
        """Every number, the strongest (largest |z| on :attr:`ranked_by`) first."""
        return sorted(self.numbers, key=lambda n: (-self._strength(n), n.name))

    @property
    def clear(self) -> list[Number]:
        """The numbers whose effect on :attr:`ranked_by` is clear, strongest first."""
        return [n for n in self.ranking if (e := n.effect(self.ranked_by)) and e.clear]

    @property
    def interaction_clear(self) -> bool:
        return self.interaction is not None and self.interaction.effect.clear

    def to_dict(self) -> dict[str, Any]:
        clear = self.clear
        return {
            "controller": self.controller,
            "profile": self.profile,
            "episodes": self.band.episodes,
            "band": {
                "episodes": self.band.episodes,
                "successes": self.band.successes,
                "success_rate": self.band.success_rate,
                "ci95_low": self.band.ci95_low,
                "ci95_high": self.band.ci95_high,
                "failures": dict(self.band.failures),
            },
            "ranked_by": self.ranked_by,
            "clear": [n.name for n in clear],
            "verdict": verdict(self),
            # noise is not ranked: with nothing clear the ranking is empty
            "ranking": [
                {"number": n.name, "clear": n in clear, **_index(n, self.ranked_by)}
                for n in (self.ranking if clear else [])
            ],
            "interaction": None if self.interaction is None else {
                **self.interaction.to_dict(), "clear": self.interaction_clear},
            "numbers": [n.to_dict() for n in self.numbers],
        }  # fmt: skip


def _index(n: Number, outcome: str) -> dict[str, Any]:
    e = n.effect(outcome)
    if e is None:
        return {"estimate": None, "ci_low": None, "ci_high": None}
    return {"estimate": e.estimate, "ci_low": e.low, "ci_high": e.high}


def verdict(a: JointAnalysis) -> str:
    """One line: what is clear at this N, or that nothing is."""
    n = a.band.episodes
    if not a.clear:
        return f"nothing is clear at N = {n}"
    names = ", ".join(x.name for x in a.clear)
    return f"clear at N = {n} ({'pass/fail' if a.ranked_by == PASS else 'progress'}): {names}"


def _drawn(row: Mapping[str, Any]) -> dict[str, dict[str, float]]:
    """Robot name → its drawn numbers, from a row's ``robot.NAME.profile_values``."""
    out = {}
    for column, text in row.items():
        if column.startswith("robot.") and column.endswith(_PROFILE_VALUES) and text:
            name = column[len("robot.") : -len(_PROFILE_VALUES)]
            values = json.loads(text) if isinstance(text, str) else dict(text)
            out[name] = {k: float(v) for k, v in values.items()}
    return out


def _shipped_values(params: Mapping[str, Any]) -> dict[str, float]:
    profile = get_profile(str(params.get("robot.profile")))
    overrides = {k[len("profile.") :]: v for k, v in params.items() if k.startswith("profile.")}
    if overrides:
        profile = apply_overrides(profile, overrides, source="profile file")
    return profile_values(profile)


def _analysis(
    controller: str,
    params: Mapping[str, Any],
    rows: list[Mapping[str, Any]],
    bins: int,
    label: str | None = None,
) -> JointAnalysis:
    outcomes = [Outcome.from_row(r) for r in rows]
    band = GroupSummary.of(controller, dict(params), outcomes)
    success = np.array([o.success for o in outcomes], dtype=float)
    progress = np.array([o.progress_laps for o in outcomes], dtype=float)
    drawn = [_drawn(r) for r in rows]
    columns: dict[tuple[str, str], list[float]] = {}
    for robots in drawn:
        for robot, values in robots.items():
            for path, value in values.items():
                columns.setdefault((robot, path), []).append(value)
    # only numbers drawn in every episode and that vary (a fixed one says nothing)
    inputs = {
        key: np.array(v)
        for key, v in columns.items()
        if len(v) == len(rows) and float(np.ptp(v)) > 0.0
    }
    shipped = _shipped_values(params)
    ranked_by = ranking_outcome(success)
    numbers = []
    for (robot, path), x in inputs.items():
        effects = {
            PASS: main_effect(x, success, PASS, len(inputs)),
            PROGRESS: main_effect(x, progress, PROGRESS, len(inputs)),
        }
        numbers.append(
            Number(
                robot,
                path,
                shipped.get(path),
                tuple(binned_curve(x, success, progress, bins)),
                effects,
            )
        )
    analysis = JointAnalysis(
        controller, label or profile_label(params), dict(params), band, tuple(numbers),
        ranked_by, None,
    )  # fmt: skip
    top = analysis.ranking
    y = success if ranked_by == PASS else progress
    pair = strongest_interaction(
        [n.name for n in top], [inputs[(n.robot, n.path)] for n in top], y, ranked_by
    )
    return dataclasses.replace(analysis, interaction=pair)


def _params(row: Mapping[str, Any]) -> dict[str, Any]:
    text = row.get("params") or "{}"
    return json.loads(text) if isinstance(text, str) else dict(text)


def analyse_rows(
    rows: Iterable[Mapping[str, Any]],
    bins: int = DEFAULT_BINS,
    wanted: Iterable[tuple[str, str]] | None = None,
    labels: Mapping[str, str] | None = None,
) -> list[JointAnalysis]:
    """One analysis per controller × parameters among ``rows`` of plausible robots (rows
    of other points, one-at-a-time's value points among them, are ignored; one row per
    key). ``wanted``: the (controller, :func:`~puckboard.sweep.plan.params_key`) groups to
    analyse, in order (default: every group, in first-seen order); ``labels``: the
    profile's name per params key (default: :func:`profile_label`)."""
    groups: dict[tuple[str, str], dict[str, Mapping[str, Any]]] = {}
    params_of: dict[tuple[str, str], dict[str, Any]] = {}
    for row in rows:
        params = _params(row)
        if params.get("variation") != PLAUSIBLE or FIELD_LABEL in params:
            continue  # not plausible robots, or a one-at-a-time value point's
        if not _drawn(row):
            continue
        group = (str(row.get("controller", "")), params_key(params))
        groups.setdefault(group, {})[str(row["key"])] = row
        params_of[group] = params
    order = list(groups) if wanted is None else [g for g in wanted if g in groups]
    names = dict(labels or {})
    return [
        _analysis(c, params_of[(c, p)], list(groups[(c, p)].values()), bins, names.get(p))
        for c, p in order
    ]


def profile_label(params: Mapping[str, Any]) -> str:
    """The profile of plausible robots' ``params`` as a reader knows it where no name came
    with the rows: the shipped profile, and the numbers a profile file set on it."""
    base = str(params.get("robot.profile"))
    own = sorted(k[len("profile.") :] for k in params if k.startswith("profile."))
    return f"{base} with {', '.join(own)} set" if own else base


@dataclass
class JointResult:
    """A joint analysis as run (or read back): what ran and what it found."""

    scenario: str
    controllers: tuple[str, ...]
    profiles: tuple[str, ...]
    seeds: str
    bins: int
    analyses: list[JointAnalysis] = field(default_factory=list)
    #: The run's own result (``None`` for an analysis read back from rows).
    sweep: SweepResult | None = None

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "method": "joint",
            "scenario": self.scenario,
            "controllers": list(self.controllers),
            "profiles": list(self.profiles),
            "seeds": self.seeds,
            "bins": self.bins,
            "episodes": sum(a.band.episodes for a in self.analyses),
        }
        if self.sweep is not None:
            out.update(self.sweep.counts(), episodes_per_s=self.sweep.episodes_per_s)
        out["analyses"] = [a.to_dict() for a in self.analyses]
        return out


def from_rows(rows: Sequence[Mapping[str, Any]], bins: int = DEFAULT_BINS) -> JointResult:
    """Recompute a joint analysis from stored rows (``puckboard sensitivity --from``)."""
    if bins < 2:
        raise PlanError(f"--bins must be at least 2, got {bins}")
    analyses = analyse_rows(rows, bins)
    if not analyses:
        raise PlanError(
            "no rows of plausible robots with their drawn numbers: write the file with "
            "puckboard sensitivity ... --method joint --out FILE (or sweep --variation "
            "plausible --out FILE)"
        )
    fewest = min(analyses, key=lambda a: a.band.episodes)
    n = fewest.band.episodes
    if n < 2 * bins:  # as a live run refuses: a bin of one episode is no rate
        fix = (
            f"use --bins {n // 2} or fewer"
            if n >= 4
            else "run more seeds (the joint method wants hundreds)"
        )
        raise PlanError(
            f"the rows hold {n} episodes of {fewest.controller} on {fewest.profile}, too few "
            f"for {bins} bins (at least 2 episodes a bin): {fix}"
        )
    scenario = str(rows[0].get("scenario", ""))
    seeds = [int(float(r.get("seed") or 0)) for r in rows if _params(r).get("variation")]
    return JointResult(
        scenario=scenario,
        controllers=tuple(dict.fromkeys(a.controller for a in analyses)),
        profiles=tuple(dict.fromkeys(a.profile for a in analyses)),
        seeds=seeds_text(seeds),
        bins=bins,
        analyses=analyses,
    )


def run_joint(
    plan: JointPlan, scene: Scene | str | Path, options: RunOptions = DEFAULT_RUN
) -> JointResult:
    """Run every episode of ``plan`` not yet in ``options.store`` (as
    :func:`~puckboard.sweep.run_sweep`) and analyse all of the plan's episodes, those the
    store held before included."""
    from ...sweep.run import run_sweep

    store = options.store
    sweep = run_sweep(plan.sweep, scene, options)
    keys = {spec.key(plan.scenario) for spec in plan.sweep.episodes()}
    rows = [r for r in (store.rows() if store is not None else sweep.rows) if r.get("key") in keys]
    point_keys = [params_key({**plan.sweep.fixed, **point}) for point in plan.sweep.points]
    wanted = [(c, key) for c in plan.sweep.controllers for key in point_keys]
    labels = dict(zip(point_keys, plan.profiles))
    return JointResult(
        scenario=plan.scenario,
        controllers=plan.sweep.controllers,
        profiles=plan.profiles,
        seeds=seeds_text(plan.sweep.seeds),
        bins=plan.bins,
        analyses=analyse_rows(rows, plan.bins, wanted, labels) if rows else [],
        sweep=sweep,
    )
