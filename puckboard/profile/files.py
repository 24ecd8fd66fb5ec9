"""Profile files: your own e-puck as a shipped profile plus the numbers you measured.

A profile file is TOML (docs/profiles.md, "Your own e-puck")::

    base = "epuck"                      # a shipped profile
    name = "my-epuck"                   # optional; default: the file's name without .toml
    source = "measured on 2026-11-24"   # the source of every value below unless it has its own

    [set]
    prox_max_distance = { value = 0.045, source = "Webots guide: about 4 cm" }
    "ir_gain.right" = 0.83
    wheel_radius = "20.3mm"

Sub-tables work too (``[set.ir_gain]`` then ``right = 0.83``). A ``[link]`` table gives
the timing of the link the robot is driven over, as ``puckboard calibrate link`` measures
and writes it: ``period`` and ``latency`` in seconds, a ``source``, and for the reader the
measured spreads (``round_trip``, ``cycle``: tables of numbers). Everything is checked on
load and every mistake is one line naming the file and the path. Scenes and recordings
keep such a profile in the same form, inline (:func:`profile_to_data`), so a run can be
repeated from its recording without the file.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import re
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..errors import ProfileError
from ..units import read_quantity
from .links import LONGEST_LINK_S
from .model import RobotProfile
from .setting_names import apply_overrides, check_setting
from .shipped import PROFILES, get_profile, profile_names

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on 3.10 only
    import tomli as tomllib

__all__ = [
    "PROFILE_SUFFIX",
    "is_profile_file",
    "link_seconds",
    "load_profile_file",
    "profile_from_data",
    "profile_to_data",
    "resolve_profile",
]

log = logging.getLogger(__name__)

PROFILE_SUFFIX = ".toml"
_TOP_KEYS = ("base", "name", "source", "set", "link")
_ENTRY_KEYS = ("value", "source")
_LINK_KEYS = ("period", "latency", "source", "round_trip", "cycle")
_TOML_WHERE = re.compile(r"\s*\(at line (\d+), column (\d+)\)\s*$")


def is_profile_file(ref: str | Path) -> bool:
    """Whether ``ref`` names a profile file rather than a shipped profile."""
    text = str(ref)
    return (
        isinstance(ref, Path)
        or text.lower().endswith(PROFILE_SUFFIX)
        or "/" in text
        or "\\" in text
    )


def load_profile_file(path: str | Path) -> RobotProfile:
    """Read and check the profile file at ``path``; :class:`ProfileError` (one line) if wrong."""
    path = Path(path)
    if path.suffix.lower() != PROFILE_SUFFIX:
        raise ProfileError(f"{path}: profile files are TOML and end in {PROFILE_SUFFIX}")
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise ProfileError(
            f"cannot read profile file {str(path)!r}: {exc.strerror or exc}"
        ) from None
    except UnicodeDecodeError:
        raise ProfileError(f"{path}: profile files must be UTF-8 text") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        message = str(exc).splitlines()[0] if str(exc) else "not valid TOML"
        where = _TOML_WHERE.search(message)
        if where is None:
            raise ProfileError(f"{path}: not valid TOML: {message}") from None
        message = message[: where.start()]
        raise ProfileError(f"{path}:{where.group(1)}:{where.group(2)}: {message}") from None
    return profile_from_data(data, source=str(path), default_name=path.stem)


def profile_from_data(
    data: Mapping[str, Any], *, source: str = "<profile>", default_name: str | None = None
) -> RobotProfile:
    """A profile from the file's form (``base``, ``name``, ``source``, ``set``), checked;
    errors are one line starting with ``source``."""
    if not isinstance(data, Mapping):
        raise ProfileError(f"{source}: expected a table with base and set, got {data!r}")
    unknown = [k for k in data if k not in _TOP_KEYS]
    if unknown:
        raise ProfileError(f"{source}: unknown key {unknown[0]!r}; known: {', '.join(_TOP_KEYS)}")
    base_name = data.get("base")
    if not isinstance(base_name, str) or not base_name:
        raise ProfileError(
            f"{source}: base: missing or not a name; give the shipped profile this one "
            f"changes: {', '.join(profile_names())}"
        )
    if base_name not in profile_names():
        raise ProfileError(
            f"{source}: base = {base_name!r}: unknown robot profile; shipped: "
            f"{', '.join(profile_names())}"
        )
    base = get_profile(base_name)
    name = data.get("name", default_name or base.name)
    if not isinstance(name, str) or not name.strip():
        raise ProfileError(f"{source}: name: expected a non-empty name, got {name!r}")
    if name in profile_names() and name != base.name:
        raise ProfileError(
            f"{source}: name = {name!r} is a shipped profile's; give this one its own name"
        )
    default_source = data.get("source", f"profile file {Path(source).name}")
    if not isinstance(default_source, str):
        raise ProfileError(f"{source}: source: expected a text, got {default_source!r}")
    values, sources = _entries(data.get("set", {}), source, default_source)
    try:
        profile = apply_overrides(base, values, source=sources)
    except ProfileError as exc:
        raise ProfileError(f"{source}: [set] {exc}") from None
    profile = dataclasses.replace(profile, name=name)
    if "link" in data:
        link, link_source = _link(data["link"], source, default_source)
        profile = dataclasses.replace(
            profile, link=link, sources={**profile.sources, "link": link_source}
        )
    return profile


def link_seconds(key: str, value: Any) -> float:
    """A link's ``period`` (> 0) or ``latency`` (>= 0) in seconds, at most
    :data:`~puckboard.profile.links.LONGEST_LINK_S`: a ``[link]`` table's, or one set as
    ``profile.link.<key>``. A number, or a text with its unit (``34ms``); else a
    one-line :class:`ProfileError` naming ``key``."""
    bound = "> 0" if key == "period" else ">= 0"
    words = f"{key}: expected seconds {bound} and <= {LONGEST_LINK_S:g}, got {value!r}"
    try:
        number = read_quantity(key, value, "s")
    except ValueError:
        raise ProfileError(words) from None
    ok = math.isfinite(number) and (number > 0 if key == "period" else number >= 0)
    if not ok or number > LONGEST_LINK_S:
        raise ProfileError(words)
    return number


def _link(table: Any, source: str, default_source: str) -> tuple[tuple[float, float], str]:
    """The ``[link]`` table as ((period, latency) in s, its source), checked."""
    if not isinstance(table, Mapping):
        raise ProfileError(f"{source}: link: expected a table with period and latency (s)")
    unknown = [k for k in table if k not in _LINK_KEYS]
    if unknown:
        raise ProfileError(
            f"{source}: [link] unknown key {unknown[0]!r}; known: {', '.join(_LINK_KEYS)}"
        )
    numbers = []
    for key in ("period", "latency"):
        try:
            numbers.append(link_seconds(key, table.get(key)))
        except ProfileError as exc:
            raise ProfileError(f"{source}: [link] {exc}") from None
    for key in ("round_trip", "cycle"):
        spread = table.get(key, {})
        if not isinstance(spread, Mapping) or not all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for v in spread.values()
        ):
            raise ProfileError(
                f"{source}: [link] {key}: expected a table of numbers, got {spread!r}"
            )
    given = table.get("source", default_source)
    if not isinstance(given, str):
        raise ProfileError(f"{source}: [link] source: expected a text, got {given!r}")
    return (numbers[0], numbers[1]), given


def _entries(
    table: Any, source: str, default_source: str, prefix: str = ""
) -> tuple[dict[str, Any], dict[str, str]]:
    """The ``[set]`` table as {path: value} and {path: source}; sub-tables become dotted paths."""
    if not isinstance(table, Mapping):
        raise ProfileError(f"{source}: set: expected a table of path = value, got {table!r}")
    values: dict[str, Any] = {}
    sources: dict[str, str] = {}
    for key, entry in table.items():
        path = f"{prefix}{key}"
        if isinstance(entry, Mapping) and "value" in entry:
            extra = [k for k in entry if k not in _ENTRY_KEYS]
            if extra:
                raise ProfileError(
                    f"{source}: [set] {path}: unknown key {extra[0]!r}; an entry has value "
                    "and source"
                )
            given = entry.get("source", default_source)
            if not isinstance(given, str):
                raise ProfileError(f"{source}: [set] {path}.source: expected a text, got {given!r}")
            values[path], sources[path] = entry["value"], given
        elif isinstance(entry, Mapping) and not prefix:
            sub_values, sub_sources = _entries(entry, source, default_source, f"{path}.")
            values.update(sub_values)
            sources.update(sub_sources)
        else:
            try:
                check_setting(path)
            except ProfileError as exc:
                raise ProfileError(f"{source}: [set] {exc}") from None
            values[path], sources[path] = entry, default_source
    return values, sources


def profile_to_data(profile: str | RobotProfile) -> str | dict[str, Any]:
    """A profile as a scene or recording stores it: a shipped profile's name, or the
    file's form (``base``, ``name``, ``source``, ``set``) that :func:`profile_from_data`
    rebuilds exactly."""
    if isinstance(profile, str):
        return profile
    if not profile.overrides and profile.link is None:
        if PROFILES.get(profile.name) != profile:
            log.warning(
                "profile %r is not a shipped one and has no recorded changes: stored by name",
                profile.name,
            )
        return profile.name
    sources = {path: profile.sources.get(path, "") for path, _ in profile.overrides}
    every = list(sources.values()) or [profile.sources.get("link", "")]
    common = max(every, key=every.count)  # the first of the most frequent: deterministic
    data: dict[str, Any] = {"base": profile.base}
    if profile.name != profile.base:
        data["name"] = profile.name
    data["source"] = common
    data["set"] = {
        path: value if sources[path] == common else {"value": value, "source": sources[path]}
        for path, value in profile.overrides
    }
    if profile.link is not None:
        data["link"] = {
            "period": profile.link[0],
            "latency": profile.link[1],
            "source": profile.sources.get("link", common),
        }
    return data


def resolve_profile(
    ref: str | Path | RobotProfile | Mapping[str, Any], *, relative_to: Path | None = None
) -> str | RobotProfile:
    """What ``--profile``, a scene's ``profile`` or an override names: a shipped profile
    (by its name, as given), a profile file (read; relative to ``relative_to``, else to
    the working directory), the file's form inline, or a profile itself."""
    if isinstance(ref, RobotProfile):
        return ref
    if isinstance(ref, Mapping):
        return profile_from_data(ref, source=str(relative_to or "<profile>"))
    if not isinstance(ref, (str, Path)):
        raise ProfileError(
            f"expected a profile name ({', '.join(profile_names())}) or a profile file, got {ref!r}"
        )
    if is_profile_file(ref):
        path = Path(ref)
        if relative_to is not None and not path.is_absolute():
            path = relative_to / path
        return load_profile_file(path)
    if ref not in profile_names():
        raise ProfileError(
            f"unknown robot profile {ref!r}; expected one of {', '.join(profile_names())} "
            "or a profile file (NAME.toml)"
        )
    return str(ref)
