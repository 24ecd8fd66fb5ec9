"""A scene's explicit form (:func:`~.conversion.scene_to_dict`) written as a TOML scene file.

``puckboard scenes show generated-pass --seed 7`` prints the scene one seed draws, for a
student to read, edit and run. Numbers are written as Python's ``repr`` gives them, the
shortest text that reads back as the same float, so the file runs the very scene that
was drawn. Only what scene files hold is written: strings, numbers, booleans, lists and
tables (top-level tables as ``[table]``, lists of tables as ``[[table]]``, tables inside
those inline).
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping
from typing import Any

__all__ = ["scene_toml"]

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def scene_toml(data: Mapping[str, Any], header: str = "") -> str:
    """``data`` (a scene's dict form) as TOML text, ``header`` as comment lines first."""
    lines = [f"# {line}".rstrip() for line in header.splitlines()]
    if lines:
        lines.append("")
    tables: list[tuple[str, Mapping[str, Any]]] = []
    arrays: list[tuple[str, list[Mapping[str, Any]]]] = []
    for key, value in data.items():
        if isinstance(value, Mapping):
            tables.append((key, value))
        elif isinstance(value, list) and value and all(isinstance(v, Mapping) for v in value):
            arrays.append((key, value))
        else:
            lines.append(f"{_key(key)} = {_value(value)}")
    for key, table in tables:
        lines += ["", f"[{_key(key)}]"]
        lines += [f"{_key(k)} = {_value(v)}" for k, v in table.items()]
    for key, items in arrays:
        for item in items:
            lines += ["", f"[[{_key(key)}]]"]
            lines += [f"{_key(k)} = {_value(v)}" for k, v in item.items()]
    return "\n".join(lines) + "\n"


def _key(key: str) -> str:
    return key if _BARE_KEY.match(key) else json.dumps(key, ensure_ascii=False)


def _value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"a scene file holds finite numbers only, got {value}")
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)  # JSON's escapes are TOML's
    if isinstance(value, Mapping):
        return "{ " + ", ".join(f"{_key(k)} = {_value(v)}" for k, v in value.items()) + " }"
    if isinstance(value, (list, tuple)):
        if len(value) > 4 and all(isinstance(v, (list, tuple)) for v in value):
            # a track's points or a polygon's vertices: one per line, to read and edit
            return "[\n" + "".join(f"    {_value(v)},\n" for v in value) + "]"
        return "[" + ", ".join(_value(v) for v in value) + "]"
    raise TypeError(f"cannot write {type(value).__name__} to a scene file")
