"""What a sensitivity analysis runs: one uncertain number at a time across its range.

A profile's numbers are readings of sources that disagree and of robots that differ
(:mod:`puckboard.profile.uncertainty`). To see which of them an outcome hangs on, each
*field* (an uncertain path: ``prox_radius.side`` moves both side sensors, ``ir_gain``
every sensor's gain) is set to evenly spaced values across its plausible range, on every
robot of the scene, while every other number keeps its shipped value. Three kinds of
point make up one controller × profile's analysis:

* ``shipped``: the profile as it is (every field's curve passes through it at the
  shipped value, when that lies in the range);
* ``value``: one field set to one value (``--set profile.PATH=VALUE`` repeats it);
* ``plausible``: every robot drawn from all the ranges at once (``--variation
  plausible``), the rate to expect of robots nobody measured.

Every point runs the same seeds (common random numbers: the same noise and start
jitter at every value), so the differences along a curve are the field's, not luck's.
The points are an ordinary :class:`~puckboard.sweep.SweepPlan` (its ``points``), run on
the sweep machinery: local cores or Dask, resumable ``--out`` rows, progress, Ctrl-C.
"""

from __future__ import annotations

import dataclasses
import difflib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ...profile import RobotProfile, apply_overrides, get_profile, uncertainty
from ...profile.setting_names import is_set, setting_unit, setting_value
from ...scenario.variation import NONE, check_variation
from ...scenario.variation import PLAUSIBLE as PLAUSIBLE_ROBOTS
from ...sweep.plan import PlanError, SweepPlan, params_key, profile_parameters

__all__ = [
    "DEFAULT_VALUES",
    "FIELD_LABEL",
    "MAX_VALUES",
    "PLAUSIBLE",
    "SHIPPED",
    "VALUE",
    "Field",
    "Point",
    "SensitivityPlan",
    "field_values",
    "sensitivity_plan",
]

#: Values per field unless asked otherwise: enough to see a curve's shape, few enough
#: that every field of a profile fits in minutes.
DEFAULT_VALUES = 7

#: At most this many values per field. Each value is a point of its own, run on every
#: seed for every controller and profile (100 values of the physical e-puck's 16 fields
#: on 20 seeds are 32,000 episodes per controller), and a curve's shape shows at a few.
MAX_VALUES = 100

#: Kinds of point: the profile as shipped, one field at one value, all fields drawn.
SHIPPED, VALUE, PLAUSIBLE = "shipped", "value", PLAUSIBLE_ROBOTS.name

#: The label (:data:`~puckboard.sweep.plan.LABEL_PREFIX`) naming the field of a value
#: point that draws every other number (``--variation plausible``). Its rows are not a
#: sample of plausible robots, and nothing in the parameters alone says so: a profile
#: file setting one number has the same shape. The joint method leaves out rows with it.
FIELD_LABEL = "label.field"


@dataclass(frozen=True)
class Field:
    """One uncertain path of one profile: its range, its shipped value and the values the
    analysis sets it to (in SI; ``unit`` as
    :func:`~puckboard.profile.setting_names.setting_unit`)."""

    profile: str
    path: str
    unit: str
    low: float
    high: float
    shipped: float
    values: tuple[float, ...]
    source: str
    kind: str

    @property
    def shipped_inside(self) -> bool:
        """Whether the shipped value lies in the range (then the shipped point is on the
        field's curve)."""
        return self.low <= self.shipped <= self.high


@dataclass(frozen=True)
class Point:
    """One set of episodes: ``kind`` :data:`SHIPPED`, :data:`VALUE` or :data:`PLAUSIBLE`;
    for a value, the ``field`` and its ``value``; ``params`` the episode parameters."""

    profile: str
    kind: str
    params: Mapping[str, Any]
    field: str = ""
    value: float | None = None


@dataclass(frozen=True)
class SensitivityPlan:
    """The analysis of ``fields`` (per profile) for every controller of ``sweep``: the
    points it runs (``sweep.points`` holds their parameters) and what each one means."""

    sweep: SweepPlan
    profiles: tuple[str, ...]
    fields: tuple[Field, ...]
    points: tuple[Point, ...]
    values: int = DEFAULT_VALUES
    #: ``plausible``: every number but the field's drawn at each value; ``none``: shipped.
    variation: str = NONE.name

    @property
    def scenario(self) -> str:
        return self.sweep.scenario

    def point_key(self, point: Point) -> str:
        """The parameters of ``point``'s episodes (the plan's fixed ones included) as
        :func:`~puckboard.sweep.plan.params_key` spells them."""
        return params_key({**self.sweep.fixed, **point.params})

    def __len__(self) -> int:
        return len(self.sweep)


def field_values(low: float, high: float, count: int) -> tuple[float, ...]:
    """``count`` evenly spaced values from ``low`` to ``high``, both ends included (one
    value, the middle, for ``count`` 1; the one value of an empty range)."""
    if count < 1:
        raise PlanError(f"--values must be at least 1, got {count}")
    if count > MAX_VALUES:
        raise PlanError(
            f"--values {count} is more than {MAX_VALUES} per field: each value runs every seed "
            f"(a curve's shape shows at a few; default {DEFAULT_VALUES}); use at most {MAX_VALUES}"
        )
    if high == low:
        return (low,)
    if count == 1:
        return ((low + high) / 2.0,)
    step = (high - low) / (count - 1)
    return tuple([low + i * step for i in range(count - 1)] + [high])


def _label(profile: RobotProfile) -> str:
    return profile.name


def _same_robot(a: RobotProfile, b: RobotProfile) -> bool:
    """Whether two profiles build the same robot (names, sources and the record of
    changes aside)."""
    # a wheel following the nominal radius (None) and one set to it roll alike
    skip = {"name", "base", "overrides", "sources", "extra", "wheel_radius_left",
            "wheel_radius_right"}  # fmt: skip
    return a.wheel_radii == b.wheel_radii and all(
        getattr(a, f.name) == getattr(b, f.name)
        for f in dataclasses.fields(a)
        if f.name not in skip
    )


def _fields_of(profile: RobotProfile, count: int) -> list[Field]:
    """Every uncertain path of ``profile`` the profile does not fix itself (a profile
    file's measured numbers define the robot), with its values."""
    out = []
    for path, spread in uncertainty(profile).items():
        if is_set(profile, path):
            continue
        out.append(
            Field(
                profile=_label(profile),
                path=path,
                unit=setting_unit(path),
                low=spread.low,
                high=spread.high,
                shipped=setting_value(profile, path),
                values=field_values(spread.low, spread.high, count),
                source=spread.source,
                kind=spread.kind,
            )
        )
    return out


def _choose(fields: list[Field], wanted: Sequence[str] | None, profiles: list[str]) -> list[Field]:
    if not wanted:
        return fields
    known = list(dict.fromkeys(f.path for f in fields))
    for path in wanted:
        if path not in known:
            close = difflib.get_close_matches(path, known, n=1)
            hint = f" (did you mean {close[0]}?)" if close else ""
            raise PlanError(
                f"--fields: {path!r} is not an uncertain field of {', '.join(profiles)}{hint}; "
                f"fields: {', '.join(known) or 'none'} (puckboard profiles show NAME lists "
                "them with their ranges)"
            )
    order = {p: i for i, p in enumerate(wanted)}
    return sorted((f for f in fields if f.path in order), key=lambda f: order[f.path])


def _value_params(
    profile: RobotProfile, base: Mapping[str, Any], field: Field, value: float, drawn: bool
) -> dict[str, Any] | None:
    """The parameters of ``field`` = ``value``; ``None`` if that builds the shipped robot
    (the shipped point stands for it, so its episodes are not run twice)."""
    changed = apply_overrides(profile, {field.path: value}, source="sensitivity")
    if not drawn and _same_robot(changed, profile):
        return None
    return {**base, f"profile.{field.path}": value}


def sensitivity_plan(
    scenario: str,
    *,
    profiles: Sequence[str | RobotProfile],
    controllers: Sequence[str],
    seeds: range,
    fields: Sequence[str] | None = None,
    values: int = DEFAULT_VALUES,
    fixed: Mapping[str, Any] | None = None,
    variation: str = NONE.name,
) -> SensitivityPlan:
    """The points of an analysis of ``scenario``: for each profile, the shipped point,
    the plausible point and ``values`` values of each uncertain field (all of them, or
    those named in ``fields``), every point for every controller on ``seeds``.

    ``variation`` ``plausible`` draws every other number of each robot at each value (the
    field's curve on robots that differ in everything else, as real ones do); ``none``
    keeps them at the profile's values. Errors are :class:`~puckboard.sweep.PlanError`,
    one line each.
    """
    if values < 1:
        raise PlanError(f"--values must be at least 1, got {values}")
    try:
        check_variation(variation)
    except ValueError as exc:
        raise PlanError(str(exc)) from None
    # reality-gap: every other number drawn, in drawn conditions too (the plausible point
    # keeps its meaning: the robots alone)
    background = {} if variation == NONE.name else {"variation": variation}
    chosen = [get_profile(p) for p in profiles]
    labels = [_label(p) for p in chosen]
    if not chosen:
        raise PlanError("a sensitivity analysis needs at least one profile")
    if len(set(labels)) != len(labels):
        raise PlanError(f"profile listed twice in {labels}")
    every = [f for profile in chosen for f in _fields_of(profile, values)]
    picked = _choose(every, fields, labels)
    points: list[Point] = []
    for profile, label in zip(chosen, labels):
        base = profile_parameters(profile)
        points.append(Point(label, SHIPPED, base))
        points.append(Point(label, PLAUSIBLE, {**base, "variation": PLAUSIBLE_ROBOTS.name}))
        for field in (f for f in picked if f.profile == label):
            for value in field.values:
                params = _value_params(profile, base, field, value, bool(background))
                if params is not None:
                    mark = {FIELD_LABEL: field.path} if background else {}
                    points.append(
                        Point(label, VALUE, {**params, **background, **mark}, field.path, value)
                    )
    if not any(f.profile in labels for f in picked) and fields:
        raise PlanError(f"--fields: none of {list(fields)} is uncertain in {', '.join(labels)}")
    sweep = SweepPlan(
        scenario=scenario,
        controllers=tuple(controllers),
        seeds=seeds,
        fixed=dict(fixed or {}),
        points=tuple(p.params for p in points),
    )
    return SensitivityPlan(sweep, tuple(labels), tuple(picked), tuple(points), values, variation)
