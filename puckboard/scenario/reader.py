"""Typed reading of one table of a scene file, with errors that name the field's path.

A scene file is data a student edits by hand, so every mistake must say which file,
which field and what was expected::

    my-scene.toml: robots[1].theta: expected a number (radians), got 'north'

:class:`TableReader` wraps one table (a TOML table or JSON object) with the path that led
to it, reads typed values with their units and bounds, and refuses keys it was never
asked for, because a misspelt key silently ignored is the hardest mistake to find.
The conversion from the file's form to a scene (:mod:`.conversion`) is written in these
calls only, so every field gets the same checks and the same kind of message.

A table that declares its keys (``keys``) refuses an unknown one before any value is
read: a misspelt ``track_distanse`` then reports itself, with the key it was probably
meant to be, instead of the ``x`` that went missing because of it.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Collection, Iterator, Mapping
from typing import Any

import numpy as np

from ..errors import SceneError

__all__ = ["TableReader", "unique_names"]


class TableReader:
    """Reads one table of the file, remembering its path for error messages."""

    def __init__(
        self, data: Any, path: str, source: str, keys: Collection[str] | None = None
    ) -> None:
        self.source = source
        self.path = path
        if not isinstance(data, Mapping):
            self.fail("", "a table (key = value pairs)", data)
        self.data: Mapping[str, Any] = data
        self.used: set[str] = set()
        if keys is not None:
            unknown = [k for k in data if k not in keys]
            if unknown:
                self._unknown(unknown[0], keys)

    def where(self, key: str) -> str:
        """The dotted path of ``key`` in the file (``robots[1].theta``)."""
        if not key:
            return self.path or "(top level)"
        return f"{self.path}.{key}" if self.path else key

    def fail(self, key: str, expected: str, got: Any = None, *, message: str = "") -> None:
        """Raise the one-line :class:`SceneError` for ``key``: what was expected and got."""
        text = message or f"expected {expected}, got {got!r}"
        raise SceneError(f"{self.source}: {self.where(key)}: {text}")

    def has(self, key: str) -> bool:
        return key in self.data

    def raw(self, key: str) -> Any:
        """The value of ``key`` unchecked (marked as used)."""
        self.used.add(key)
        return self.data[key]

    def number(
        self,
        key: str,
        default: float | None = None,
        *,
        unit: str = "",
        low: float | None = None,
        high: float | None = None,
        low_open: bool = False,
        required: bool = False,
    ) -> float:
        """A finite number within [``low``, ``high``] (``low`` excluded if ``low_open``)."""
        if key not in self.data:
            if required or default is None:
                self.fail(key, "", message=f"missing; expected a number{_unit(unit)}")
            return float(default)  # type: ignore[arg-type]
        value = self.raw(key)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            self.fail(key, f"a number{_unit(unit)}", value)
        value = float(value)
        if not math.isfinite(value):
            self.fail(key, f"a finite number{_unit(unit)}", value)
        if low is not None and (value <= low if low_open else value < low):
            self.fail(key, f"a number {'>' if low_open else '>='} {low:g}{_unit(unit)}", value)
        if high is not None and value > high:
            self.fail(key, f"a number <= {high:g}{_unit(unit)}", value)
        return value

    def angle(self, key: str, default: float | None = None, *, required: bool = False) -> float:
        """``key`` in radians or ``key_deg`` in degrees (not both); stored in radians."""
        deg_key = f"{key}_deg"
        if key in self.data and deg_key in self.data:
            self.fail(key, "", message=f"give either {key} (radians) or {deg_key}, not both")
        if deg_key in self.data:
            return math.radians(self.number(deg_key, unit="degrees"))
        if key not in self.data and not required and default is not None:
            return default
        if key not in self.data:
            self.fail(key, "", message=f"missing; expected {key} (radians) or {deg_key} (degrees)")
        return self.number(key, unit="radians")

    def string(self, key: str, default: str | None = None, *, choices: tuple[str, ...] = ()) -> str:
        """A string, one of ``choices`` when given."""
        if key not in self.data:
            if default is None:
                self.fail(key, "", message="missing; expected a string")
            return default  # type: ignore[return-value]
        value = self.raw(key)
        if not isinstance(value, str):
            self.fail(key, "a string", value)
        if choices and value not in choices:
            self.fail(key, f"one of {', '.join(choices)}", value)
        return value  # type: ignore[no-any-return]

    def boolean(self, key: str, default: bool) -> bool:
        if key not in self.data:
            return default
        value = self.raw(key)
        if not isinstance(value, bool):
            self.fail(key, "true or false", value)
        return value  # type: ignore[no-any-return]

    def colour(self, key: str, default: tuple[int, int, int]) -> tuple[int, int, int]:
        """An ``[r, g, b]`` triple of integers 0..255."""
        if key not in self.data:
            return default
        value = self.raw(key)
        ok = (
            isinstance(value, list)
            and len(value) == 3
            and all(isinstance(c, int) and not isinstance(c, bool) and 0 <= c <= 255 for c in value)
        )
        if not ok:
            self.fail(key, "an [r, g, b] colour with integers 0..255", value)
        return (value[0], value[1], value[2])

    def pair(self, key: str, *, unit: str = "m", positive: bool = False) -> tuple[float, float]:
        """A pair ``[a, b]`` of finite numbers (both > 0 if ``positive``)."""
        value = self.raw(key)
        ok = (
            isinstance(value, list)
            and len(value) == 2
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
            and all(math.isfinite(v) for v in value)
        )
        if not ok:
            self.fail(key, f"a pair [a, b] of numbers ({unit})", value)
        if positive and min(value) <= 0:
            self.fail(key, f"a pair of positive numbers ({unit})", value)
        return (float(value[0]), float(value[1]))

    def points(self, key: str, minimum: int) -> np.ndarray:
        """At least ``minimum`` ``[x, y]`` points (m) as an M×2 array."""
        value = self.raw(key)
        if not isinstance(value, list) or len(value) < minimum:
            self.fail(key, f"a list of at least {minimum} [x, y] points (m)", value)
        out = np.empty((len(value), 2))
        for i, p in enumerate(value):
            ok = (
                isinstance(p, list)
                and len(p) == 2
                and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in p)
                and all(math.isfinite(v) for v in p)
            )
            if not ok:
                self.fail(f"{key}[{i}]", "an [x, y] pair of numbers (m)", p)
            out[i] = p
        return out

    def table_list(self, key: str) -> list[Any]:
        """A list of tables (``[[key]]`` in TOML); empty when the key is absent."""
        if key not in self.data:
            return []
        value = self.raw(key)
        if not isinstance(value, list):
            self.fail(key, "a list of tables ([[...]] in TOML)", value)
        return value  # type: ignore[no-any-return]

    def sub(self, key: str, keys: Collection[str] | None = None) -> TableReader | None:
        """A reader of the sub-table ``key`` (refusing keys not in ``keys`` at once, when
        given), or None when it is absent."""
        if key not in self.data:
            return None
        return TableReader(self.raw(key), self.where(key), self.source, keys)

    def items(self, key: str, keys: Collection[str] | None = None) -> Iterator[TableReader]:
        """A reader for each table of the list ``key`` (``robots[0]``, ``robots[1]`` ...),
        made as it is reached, so the first mistake in file order is the one reported."""
        where = self.where(key)
        for i, item in enumerate(self.table_list(key)):
            yield TableReader(item, f"{where}[{i}]", self.source, keys)

    def finish(self, extra_allowed: tuple[str, ...] = ()) -> None:
        """Refuse keys that were not read: unknown ones, or ones that mean nothing in this
        table's case (a ``radius`` on a box); a typo would otherwise be silently ignored."""
        unknown = [k for k in self.data if k not in self.used and k not in extra_allowed]
        if unknown:
            self._unknown(unknown[0], self.used | set(extra_allowed))

    def _unknown(self, key: str, known: Collection[str]) -> None:
        """Fail on ``key``, naming the known key it is closest to, if one is close."""
        close = difflib.get_close_matches(str(key), [str(k) for k in known], n=1)
        guess = f"; did you mean {close[0]!r}?" if close else ""
        listed = f" (known here: {', '.join(sorted(known))})" if known else ""
        self.fail(str(key), "", message=f"unknown key{guess}{listed}")


def unique_names(names: list[str], table: str, source: str) -> None:
    """Refuse a name used twice in one list of tables (robots and dummies are found by name)."""
    seen: set[str] = set()
    for i, name in enumerate(names):
        if name in seen:
            raise SceneError(
                f"{source}: {table}[{i}].name: {name!r} is used twice; names must be unique"
            )
        seen.add(name)


def _unit(unit: str) -> str:
    return f" ({unit})" if unit else ""
