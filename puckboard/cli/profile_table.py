"""The table ``puckboard profiles show`` prints: every path of a profile with its value,
its plausible range and where that comes from.

Rows follow the paths a user sets (:mod:`puckboard.profile.setting_names`), grouped as people
read them: a symmetric pair of IR sensors is one row while its two sensors agree. A
profile file is shown beside the shipped profile it changes. docs/profiles.md holds the
Markdown form of the shipped profiles' tables, and a test keeps the two equal.
"""

from __future__ import annotations

import math
from typing import Any

from ..profile import (
    PROX_GROUPS,
    Range,
    RobotProfile,
    get_profile,
    profile_values,
    uncertainty,
)
from ..profile.setting_names import SETTING_FIELDS, expand_setting, setting_unit, setting_value
from ..profile.uncertainty import certainty_note
from ..records import PROX_NAMES

__all__ = ["path_rows", "path_table_json", "path_table_markdown", "path_table_text"]

#: The rows every profile shows, before any path a profile sets on its own.
_ROWS: tuple[str, ...] = (
    "wheel_radius",
    "wheel_radius.left",
    "wheel_radius.right",
    "axle_length",
    "body_radius",
    "max_wheel_speed",
    "prox_aperture",
    "prox_min_distance",
    "prox_max_distance",
    *(f"prox_radius.{g}" for g in PROX_GROUPS),
    *(f"prox_heading.{g}" for g in PROX_GROUPS),
    "ir_gain",
    "ir_offset",
    "ground_spacing",
    "ground_forward",
    "ground_footprint",
)


def _number(value: float, unit: str) -> str:
    if unit == "m":
        return f"{round(value * 1000, 2):g}"
    if unit == "rad":
        return f"{round(math.degrees(value), 2):g}"
    return f"{round(value, 4):g}"


def _suffix(unit: str) -> str:
    return {"m": " mm", "rad": "°", "rad/s": " rad/s"}.get(unit, "")


def _value_text(profile: RobotProfile, path: str) -> str:
    """A row's value in display units; a group whose sensors differ shows each."""
    unit = setting_unit(path)
    singles = expand_setting(path)
    head, _, suffix = path.partition(".")
    values = [setting_value(profile, p) for p in singles]
    if head == "prox_heading" and suffix in PROX_GROUPS:
        left, right = PROX_GROUPS[suffix]
        values = [setting_value(profile, f"{head}.{PROX_NAMES[left]}")]
        values.append(-setting_value(profile, f"{head}.{PROX_NAMES[right]}"))
        singles = (f"{head}.{PROX_NAMES[left]}", f"{head}.{PROX_NAMES[right]}")
    common = max(values, key=values.count)
    text = _number(common, unit) + _suffix(unit)
    others = [
        f"{p.partition('.')[2]}: {_number(v, unit)}{_suffix(unit)}"
        for p, v in zip(singles, values)
        if v != common
    ]
    return f"{text} ({', '.join(others)})" if others else text


def _range_text(low: float, high: float, unit: str) -> str:
    return f"{_number(low, unit)}–{_number(high, unit)}{_suffix(unit)}"


def path_rows(profile: RobotProfile) -> list[str]:
    """The rows shown for ``profile``: the standard ones and every path it sets."""
    rows = list(_ROWS)
    for path, _ in profile.overrides:
        if path not in rows and path != "ir_gain.all":
            rows.append(path)
    order = {head: i for i, head in enumerate(SETTING_FIELDS)}
    rows.sort(key=lambda p: order[p.partition(".")[0]])  # stable: standard rows keep order
    return rows


def _source_text(profile: RobotProfile, path: str) -> tuple[str, str]:
    """(range, source) cells: the plausible range, and where the value (if set) and the
    range come from."""
    unit = setting_unit(path)
    found = uncertainty(profile).get(path)
    parts = []
    if path in dict(profile.overrides):
        given = profile.sources.get(path, "")
        parts.append(f"set: {given}" if given else "set")
    range_cell = ""
    if found is not None:
        range_cell = _range_text(found.low, found.high, unit)
        parts.append(f"{found.kind}: {found.source}")
    elif certainty_note(profile, path):
        parts.append(f"no range: {certainty_note(profile, path)}")
    return range_cell, "; ".join(parts)


def _cells(profile: RobotProfile, path: str) -> list[str]:
    range_cell, source = _source_text(profile, path)
    return [f"`{path}`", _value_text(profile, path), range_cell, source]


def path_table_markdown(profile: RobotProfile) -> str:
    """The Markdown table of ``profile``'s paths (beside its base when it has one)."""
    base = _base(profile)
    head = ["path", f"`{profile.name}`", "plausible range", "source"]
    if base is not None:
        head.insert(1, f"`{base.name}`")
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for path in path_rows(profile):
        cells = _cells(profile, path)
        if base is not None:
            cells.insert(1, _value_text(base, path))
        lines.append("| " + " | ".join(cells) + " |")
    if profile.link is not None:
        period, latency = profile.link
        lines.append(
            f"\n`[link]`: period {period * 1000:g} ms, latency {latency * 1000:g} ms "
            f"({profile.sources.get('link', '')})"
        )
    return "\n".join(lines)


def path_table_text(profile: RobotProfile) -> str:
    """The same table as plain columns for a terminal (the source on its own line)."""
    base = _base(profile)
    title = profile.name + (f" (changes {base.name})" if base is not None else "")
    lines = [title]
    for path in path_rows(profile):
        _, value, range_cell, source = _cells(profile, path)
        was = f"   ({base.name}: {_value_text(base, path)})" if base is not None else ""
        changed = base is not None and _value_text(base, path) != value
        row = f"  {path:<24}{value:<22}{range_cell:<18}"
        lines.append((row + (was if changed else "")).rstrip())
        if source:
            lines.append(f"      {source}")
    return "\n".join(lines + _link_lines(profile))


def _link_lines(profile: RobotProfile) -> list[str]:
    """The profile's measured link (a ``[link]`` table), which every run with the file
    takes as its loop's timing."""
    if profile.link is None:
        return []
    period, latency = profile.link
    source = profile.sources.get("link", "")
    return [
        "  [link]: the loop's timing every run takes from this profile (rounded to whole "
        "steps of dt; a --set control.* replaces it)",
        f"  {'link.period':<24}{period * 1000:g} ms",
        f"  {'link.latency':<24}{latency * 1000:g} ms",
        *([f"      source: {source}"] if source else []),
    ]


def path_table_json(profile: RobotProfile) -> dict[str, Any]:
    """Every single number (``prox_radius.right``, not ``.side``) with its unit, value,
    range and sources, SI."""
    base = _base(profile)
    ranges = uncertainty(profile)
    by_single: dict[str, Range] = {}
    for path, plausible in ranges.items():
        for single in expand_setting(path):
            by_single[single] = plausible
    values = profile_values(profile)
    set_by = {
        single: profile.sources.get(path, "")
        for path, _ in profile.overrides
        for single in expand_setting(path)
    }
    rows = []
    singles: list[str] = []
    for path in path_rows(profile):
        singles += [s for s in expand_setting(path) if s not in singles]
    for single in singles:
        found = by_single.get(single)
        value = values.get(single, setting_value(profile, single))
        row: dict[str, Any] = {"path": single, "unit": setting_unit(single), "value": value}
        if base is not None:
            row["base_value"] = setting_value(base, single)
        if found is not None:
            low, high = found.low, found.high
            if single.startswith("prox_heading.") and value < 0:
                low, high = -high, -low  # a right sensor's range is the mirror image
            row.update(low=low, high=high, kind=found.kind, range_source=found.source)
        if single in set_by:
            row["set_source"] = set_by[single]
        rows.append(row)
    out: dict[str, Any] = {"name": profile.name, "paths": rows}
    if profile.link is not None:
        out["link"] = {
            "period": profile.link[0],
            "latency": profile.link[1],
            "source": profile.sources.get("link", ""),
        }
    if base is not None:
        out["base"] = base.name
        out["set"] = [
            {"path": p, "value": v, "source": profile.sources.get(p, "")}
            for p, v in profile.overrides
        ]
    return out


def _base(profile: RobotProfile) -> RobotProfile | None:
    """The shipped profile ``profile`` changes (``None`` for a shipped one)."""
    if not profile.overrides or not profile.base:
        return None
    return get_profile(profile.base)
