"""Setting names: the names a user sets a robot-model number by, with what makes sense.

A setting name (``profile.<setting>`` on the command line) is a dotted name into the
robot model. Setting names are the one dialect every profile change speaks: ``--set
profile.<setting>=VALUE``, a profile file's ``set`` table, a scene's inline profile, a
sweep's and a sensitivity analysis's points.

A setting names one number of a :class:`~puckboard.profile.model.RobotProfile` the way a
person thinks of it (``prox_max_distance``, ``prox_radius.side``, ``ir_gain.right``),
not the way the record stores it (a tuple of sensor poses). Sensors go by name
(:data:`puckboard.records.PROX_NAMES`), never by index, and the symmetric pairs by group:
``front`` (front_right + front_left), ``diagonal``, ``side`` (right + left), ``rear``,
and ``all``. A heading set on a pair is the left sensor's (positive) heading; the right
one gets its mirror image, so a pair stays symmetric.

Every value is checked against hard bounds of physical sense (a wheel of 5 to 50 mm, an
aperture between 0 and π, a gain between 0 and 10 ...): not what is plausible (that is
:mod:`puckboard.profile.uncertainty`), what is possible at all, so that a typo (``31``
for 31 mm) is one clear line instead of a robot the simulator cannot build. A value may
be a number in SI units or a string with a unit: ``"31mm"``, ``"3.1cm"``, ``"17deg"``.

:func:`apply_overrides` returns a new profile and records every change, so the profile
can be written down as its base plus the changes and rebuilt exactly. Changes apply from
the broad to the specific (``ir_gain`` before ``ir_gain.side`` before ``ir_gain.right``),
whatever order they are given in: the most specific setting wins.
"""

from __future__ import annotations

import dataclasses
import difflib
import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Any

from ..errors import ProfileError
from ..records import PROX_NAMES
from ..units import read_quantity
from .model import RobotProfile

__all__ = [
    "PROX_GROUPS",
    "SETTING_FIELDS",
    "apply_overrides",
    "check_setting",
    "check_value",
    "concrete_settings",
    "describe_settings",
    "expand_setting",
    "is_set",
    "recorded_numbers",
    "setting_unit",
    "setting_value",
]

#: The symmetric pairs of IR sensors as (left, right) sensor indices, by group name.
PROX_GROUPS: dict[str, tuple[int, int]] = {
    "front": (7, 0),
    "diagonal": (6, 1),
    "side": (5, 2),
    "rear": (4, 3),
}
_ALL = "all"


@dataclass(frozen=True)
class _Field:
    """One settable kind of number: its unit, its hard bounds and how it takes a sensor."""

    unit: str  # "m", "rad", "rad/s", "1" or "raw"
    low: float
    high: float
    low_open: bool
    high_open: bool
    meaning: str
    sensors: str = ""  # "": a plain number; "ir": .<sensor or group>; "wheel": .left/.right
    bare: bool = True  # may be given without a suffix (a sensor field: meaning all)
    pairs_mirror: bool = False  # a pair's value is the left sensor's; the right is mirrored

    def interval(self) -> str:
        lo = "(" if self.low_open else "["
        hi = ")" if self.high_open else "]"
        return f"{lo}{_show(self.low, self.unit)}, {_show(self.high, self.unit)}{hi}"


#: Every setting head, in the order reports list them.
SETTING_FIELDS: dict[str, _Field] = {
    "wheel_radius": _Field(
        "m",
        0.005,
        0.05,
        False,
        False,
        "wheel radius: the nominal one (conversions, odometry) and both wheels; "
        ".left/.right: one wheel's true radius only",
        sensors="wheel",
    ),
    "axle_length": _Field("m", 0.01, 0.2, False, False, "distance between the wheels"),
    "body_radius": _Field("m", 0.0, 0.1, True, True, "collision radius of the body"),
    "max_wheel_speed": _Field("rad/s", 0.0, 100.0, True, False, "wheel speed limit"),
    "prox_aperture": _Field("rad", 0.0, math.pi, True, True, "opening angle of each IR sensor"),
    "prox_max_distance": _Field(
        "m",
        0.0,
        0.1,
        True,
        False,
        "detection cut-off: farther readings report nothing (prox_range)",
    ),
    "prox_min_distance": _Field(
        "m", 0.0, 0.1, False, True, "nearest distance an IR sensor detects"
    ),
    "prox_radius": _Field(
        "m",
        0.0,
        0.1,
        True,
        True,
        "distance of an IR sensor from the robot's centre, moved along its bearing",
        sensors="ir",
        bare=False,
    ),
    "prox_heading": _Field(
        "rad",
        -math.pi,
        math.pi,
        False,
        False,
        "look direction of an IR sensor; for a pair the left sensor's, mirrored on the right",
        sensors="ir",
        bare=False,
        pairs_mirror=True,
    ),
    "ir_gain": _Field(
        "1",
        0.0,
        10.0,
        True,
        False,
        "multiplier of an IR sensor's response above its ambient baseline",
        sensors="ir",
    ),
    "ir_offset": _Field(
        "raw",
        -4095.0,
        4095.0,
        False,
        False,
        "raw units added to an IR sensor's calibrated value",
        sensors="ir",
    ),
    "ground_spacing": _Field(
        "m",
        0.0,
        0.05,
        True,
        False,
        "lateral distance between adjacent ground sensors (the centre one stays)",
    ),
    "ground_forward": _Field(
        "m", -0.1, 0.1, False, False, "how far ahead of the axle the ground sensors sit"
    ),
    "ground_footprint": _Field(
        "m", 0.0, 0.02, False, False, "half-width of a ground sensor's light spot"
    ),
}


def _show(value: float, unit: str) -> str:
    """A bound as people read it: mm and degrees beside the SI value."""
    if unit == "m":
        return f"{value:g} m ({value * 1000:g} mm)" if value else "0"
    if unit == "rad":
        return f"{value:.4g} rad ({math.degrees(value):.4g}°)" if value else "0"
    return f"{value:g}" if unit in ("1", "raw") else f"{value:g} {unit}"


@dataclass(frozen=True)
class _Target:
    """What one setting changes: a field, and which of its sensors (or wheels)."""

    head: str
    suffix: str  # "" (bare), a sensor name, a group name, "all", "left" or "right"
    sensors: tuple[int, ...]  # IR sensor indices (ir fields); () otherwise
    rank: int  # 0 whole field, 1 a pair, 2 one sensor or wheel: broad applies first

    @property
    def field(self) -> _Field:
        return SETTING_FIELDS[self.head]

    @property
    def cover(self) -> frozenset[str]:
        """The numbers this setting sets, to drop older, narrower changes it replaces."""
        if self.sensors:
            return frozenset(str(i) for i in self.sensors)
        if self.head == "wheel_radius":
            return frozenset({self.suffix} if self.suffix else {"nominal", "left", "right"})
        return frozenset({""})

    def order(self) -> tuple[int, int, int]:
        head = list(SETTING_FIELDS).index(self.head)
        return head, self.rank, self.sensors[0] if len(self.sensors) == 1 else -1


def _resolve(setting: str) -> _Target:
    """The target of ``setting``; :class:`ProfileError` naming the known settings if none."""
    head, dot, suffix = str(setting).strip().partition(".")
    spec = SETTING_FIELDS.get(head)
    if spec is None or (dot and not spec.sensors) or (not dot and not spec.bare):
        raise ProfileError(_unknown_setting(setting))
    if not dot:
        return _Target(head, "", tuple(range(len(PROX_NAMES))) if spec.sensors == "ir" else (), 0)
    if spec.sensors == "wheel":
        if suffix in ("left", "right"):
            return _Target(head, suffix, (), 2)
        raise ProfileError(_unknown_setting(setting, f"{head}.left or {head}.right"))
    if suffix in PROX_NAMES:
        return _Target(head, suffix, (PROX_NAMES.index(suffix),), 2)
    if suffix in PROX_GROUPS:
        return _Target(head, suffix, PROX_GROUPS[suffix], 1)
    if suffix == _ALL and not spec.pairs_mirror:
        return _Target(head, suffix, tuple(range(len(PROX_NAMES))), 0)
    groups = [g for g in (*PROX_GROUPS, _ALL) if g != _ALL or not spec.pairs_mirror]
    close = difflib.get_close_matches(suffix, [*PROX_NAMES, *groups], n=1)
    hint = f" (did you mean {head}.{close[0]}?)" if close else ""
    raise ProfileError(
        f"unknown sensor or group {suffix!r} in profile setting {setting!r}{hint}; sensors: "
        f"{', '.join(PROX_NAMES)}; groups: {', '.join(groups)}"
    )


def concrete_settings() -> list[str]:
    """Every setting there is, spelled out (for suggestions and completion)."""
    out = []
    for head, spec in SETTING_FIELDS.items():
        if spec.bare:
            out.append(head)
        if spec.sensors == "wheel":
            out += [f"{head}.left", f"{head}.right"]
        elif spec.sensors == "ir":
            groups = [*PROX_GROUPS] + ([] if spec.pairs_mirror else [_ALL])
            out += [f"{head}.{s}" for s in (*groups, *PROX_NAMES)]
    return out


def describe_settings() -> str:
    """The settings in one line: ``wheel_radius[.left|.right], ..., prox_radius.<sensor|group>``."""
    parts = []
    for head, spec in SETTING_FIELDS.items():
        if spec.sensors == "wheel":
            parts.append(f"{head}[.left|.right]")
        elif spec.sensors == "ir":
            parts.append(f"{head}[.<sensor|group>]" if spec.bare else f"{head}.<sensor|group>")
        else:
            parts.append(head)
    return ", ".join(parts)


def _unknown_setting(setting: str, expected: str = "") -> str:
    close = difflib.get_close_matches(str(setting).strip(), concrete_settings(), n=1, cutoff=0.6)
    hint = f" (did you mean {close[0]}?)" if close else ""
    if expected:
        return f"unknown profile setting {setting!r}{hint}; expected {expected}"
    return (
        f"unknown profile setting {setting!r}{hint}; settings: {describe_settings()} (sensors: "
        f"{', '.join(PROX_NAMES)}; groups: {', '.join(PROX_GROUPS)}, all)"
    )


def check_setting(setting: str) -> str:
    """``setting`` stripped, if it names something; else :class:`ProfileError` (one line)."""
    _resolve(setting)
    return str(setting).strip()


def setting_unit(setting: str) -> str:
    """The SI unit of ``setting``'s values: ``m``, ``rad``, ``rad/s``, ``1`` or ``raw``."""
    return _resolve(setting).field.unit


def check_value(setting: str, value: Any) -> float:
    """``value`` for ``setting`` as an SI float, within the setting's hard bounds.

    Numbers are SI; a string may carry a unit (``"31mm"``, ``"17deg"``). Wrong type,
    wrong unit or a value out of bounds is a :class:`ProfileError` naming the setting, the
    value and the allowed interval.
    """
    target = _resolve(setting)
    spec = target.field
    number = _number(setting, value, spec.unit)
    low, high = spec.low, spec.high
    if target.suffix in PROX_GROUPS and spec.pairs_mirror:
        low = 0.0  # a pair's heading is the left sensor's, which looks left
    too_low = number <= low if spec.low_open else number < low
    too_high = number >= high if spec.high_open else number > high
    if too_low or too_high or not math.isfinite(number):
        interval = dataclasses.replace(spec, low=low).interval()
        raise ProfileError(
            f"{setting} = {_given(value)}: outside {interval} ({spec.meaning}); "
            f"give a value in that interval"
        )
    return number


def _given(value: Any) -> str:
    return value if isinstance(value, str) else f"{value!r}"


def _number(setting: str, value: Any, unit: str) -> float:
    try:
        return read_quantity(setting, value, unit)
    except ValueError as exc:
        raise ProfileError(str(exc)) from None


def expand_setting(setting: str) -> tuple[str, ...]:
    """The single-number settings ``setting`` sets: ``prox_radius.side`` →
    (``prox_radius.right``, ``prox_radius.left``); a plain setting is itself."""
    target = _resolve(setting)
    if target.sensors:
        return tuple(f"{target.head}.{PROX_NAMES[i]}" for i in sorted(target.sensors))
    return (target.head if not target.suffix else f"{target.head}.{target.suffix}",)


def setting_value(profile: RobotProfile, setting: str) -> float:
    """The value of ``setting`` on ``profile`` (a pair gives its left sensor's value, a
    whole-ring setting ps0's)."""
    target = _resolve(setting)
    head = target.head
    if target.sensors:
        index = target.sensors[0] if target.rank else 0
        if head == "prox_radius":
            pose = profile.prox_poses[index]
            return math.hypot(pose.x, pose.y)
        if head == "prox_heading":
            return profile.prox_poses[index].heading
        return float(getattr(profile, head)[index])
    if head == "wheel_radius" and target.suffix:
        return profile.wheel_radii[0 if target.suffix == "left" else 1]
    if head == "ground_spacing":
        poses = profile.ground_poses
        return (poses[0].y - poses[-1].y) / (len(poses) - 1)
    if head == "ground_forward":
        return profile.ground_poses[len(profile.ground_poses) // 2].x
    return float(getattr(profile, head))


def _numbers(record: list[tuple[str, float]]) -> dict[str, float | None]:
    """Each single number the ``record`` sets, by its single-number setting: the last entry
    (broad to specific) covering it wins; ``None`` for a wheel that follows the nominal."""
    out: dict[str, float | None] = {}
    for setting, value in record:
        target = _resolve(setting)
        if target.head == "wheel_radius" and not target.suffix:
            out.update(
                {"wheel_radius": value, "wheel_radius.left": None, "wheel_radius.right": None}
            )
        elif target.sensors:
            left = PROX_GROUPS[target.suffix][0] if target.rank == 1 else -1
            mirror = target.field.pairs_mirror and target.rank == 1
            for i in target.sensors:
                out[f"{target.head}.{PROX_NAMES[i]}"] = -value if mirror and i != left else value
        else:
            out[expand_setting(setting)[0]] = value
    return out


def _set(
    profile: Any, setting: str, value: float | None
) -> dict[str, Any]:  # Any: a RobotProfile's fields as a SimpleNamespace (checked once, at the end)
    """The field changes that give ``profile`` ``value`` at the single-number ``setting``."""
    target = _resolve(setting)
    head = target.head
    if head == "wheel_radius":
        return {f"wheel_radius_{target.suffix}" if target.suffix else head: value}
    assert value is not None
    if head in ("prox_radius", "prox_heading"):
        (i,) = target.sensors
        poses = list(profile.prox_poses)
        pose = poses[i]
        if head == "prox_heading":
            poses[i] = dataclasses.replace(pose, heading=value)
        else:
            scale = value / math.hypot(pose.x, pose.y)  # exactly 1 for the same radius
            poses[i] = dataclasses.replace(pose, x=pose.x * scale, y=pose.y * scale)
        return {"prox_poses": tuple(poses)}
    if head in ("ir_gain", "ir_offset"):
        (i,) = target.sensors
        values = list(getattr(profile, head))
        values[i] = value
        return {head: tuple(values)}
    if head == "ground_spacing":
        poses = profile.ground_poses
        now = setting_value(profile, "ground_spacing")
        if value == now:
            return {}
        centre = poses[len(poses) // 2].y
        moved = tuple(
            dataclasses.replace(q, y=centre + (q.y - centre) * value / now) for q in poses
        )
        return {"ground_poses": moved}
    if head == "ground_forward":
        return {
            "ground_poses": tuple(dataclasses.replace(q, x=value) for q in profile.ground_poses)
        }
    return {head: value}


def _source_of(source: str | Mapping[str, str], setting: str) -> str:
    if isinstance(source, str):
        return source
    return str(source.get(setting, source.get("", "")))


def _merge(
    record: list[tuple[str, float]], setting: str, value: float, sources: dict[str, str]
) -> list[tuple[str, float]]:
    """``record`` with ``setting = value`` added, dropping the older changes it replaces."""
    target = _resolve(setting)
    kept = []
    for old_setting, old_value in record:
        old = _resolve(old_setting)
        if old.head == target.head and old.cover <= target.cover:
            sources.pop(old_setting, None)
        else:
            kept.append((old_setting, old_value))
    return [*kept, (setting, value)]


def apply_overrides(
    profile: RobotProfile,
    overrides: Mapping[str, Any],
    *,
    source: str | Mapping[str, str],
) -> RobotProfile:
    """A new profile: ``profile`` with ``{setting: value}`` set, each change checked.

    ``source`` says where the values come from (one text for all, or one per setting;
    ``""`` in a mapping is the default), and lands in the new profile's ``sources`` under
    each setting. The result keeps ``profile``'s name, names its shipped ``base`` and adds
    the changes to ``overrides`` (a later change of the same number replaces an earlier
    one), so ``base`` + ``overrides`` rebuild it: every number is set once, on the base,
    to the value of the most specific change naming it. Errors are
    :class:`ProfileError`, one line naming the setting, the value and what is allowed.
    """
    from .shipped import PROFILES

    checked = [(str(p).strip(), check_value(p, v), v) for p, v in overrides.items()]
    checked.sort(key=lambda item: _resolve(item[0]).order())
    sources = dict(profile.sources)
    record = list(profile.overrides)
    for setting, value, _ in checked:
        record = _merge(record, setting, value, sources)
        sources[setting] = _source_of(source, setting)
    record.sort(key=lambda item: _resolve(item[0]).order())
    if profile.overrides:
        base = profile.base
        origin = PROFILES.get(base) if base else None
    else:
        base = profile.name if PROFILES.get(profile.name) == profile else ""
        origin = profile
    numbers = _numbers(record if origin is not None else [(p, v) for p, v, _ in checked])
    start = origin if origin is not None else profile
    # the fields as plain attributes: the record checks its invariants once, at the end
    current = SimpleNamespace(**{f.name: getattr(start, f.name) for f in dataclasses.fields(start)})
    for single, number in numbers.items():
        vars(current).update(_set(current, single, number))
    _check_detection(current, [(setting, given) for setting, _, given in checked])
    return dataclasses.replace(
        start,
        **{k: v for k, v in vars(current).items() if getattr(start, k) is not v},
        name=profile.name,
        base=base,
        overrides=tuple(record),
        sources=sources,
        extra=dict(profile.extra),
        link=profile.link,  # its measured link is not a number these settings change
    )


def recorded_numbers(profile: RobotProfile) -> dict[str, float | None]:
    """The single numbers ``profile``'s overrides set, by single-number setting."""
    return _numbers(list(profile.overrides))


def _check_detection(
    profile: Any, given: list[tuple[str, Any]]
) -> None:  # Any: a RobotProfile's fields as a SimpleNamespace (checked once, at the end)
    """0 <= prox_min_distance < prox_max_distance <= prox_range, named by the setting set."""
    lo, hi, rng = profile.prox_min_distance, profile.prox_max_distance, profile.prox_range
    if lo < hi <= rng:
        return
    named = dict(given)
    if "prox_max_distance" in named or "prox_min_distance" not in named:
        setting = "prox_max_distance"
        allowed = (
            f"({lo:g} m, {rng:g} m]: beyond prox_min_distance and within prox_range, the "
            "distance a reading of nothing reports"
        )
    else:
        setting = "prox_min_distance"
        allowed = f"[0, {hi:g} m): short of prox_max_distance"
    value = _given(named[setting]) if setting in named else f"{getattr(profile, setting):g}"
    raise ProfileError(f"{setting} = {value}: outside {allowed}")


def is_set(profile: RobotProfile, setting: str) -> bool:
    """Whether ``profile``'s overrides already fix every number ``setting`` names."""
    target = _resolve(setting)
    for old_setting, _ in profile.overrides:
        old = _resolve(old_setting)
        if old.head == target.head and target.cover <= old.cover:
            return True
    return False
