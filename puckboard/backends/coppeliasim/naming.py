"""Robot object names: which objects of a CoppeliaSim scene make up one e-puck.

The robot is found by the stock model's deprecated names (``ePuck``, ``ePuck#0`` ...:
``ePuck_leftJoint#0`` and so on) or by a CoppeliaSim 4.3+ alias path (``/ePuck[1]``:
``/ePuck[1]/leftJoint``). A scene saved by one CoppeliaSim release may answer only one
style, so both are offered, the one the user wrote first; a missing robot is then an
error that lists every name looked for.
"""

from __future__ import annotations

import re
from typing import Any

__all__ = ["robot_object_names", "show_name"]


def robot_object_names(object_path: str) -> list[dict[str, Any]]:
    """The object names to try for robot ``object_path``, best first.

    Each entry maps part → name (or ``(path, index)`` for the IR sensors of an alias
    path): the deprecated V-REP names for ``ePuck#0``, alias paths for ``/ePuck[1]``,
    and the other style as the second choice.
    """
    styles = []
    m_name = re.fullmatch(r"(?P<model>[^/#\s]+)(?:#(?P<n>\d+))?", object_path)
    m_path = re.fullmatch(r"/(?P<model>[^/\[\]{}]+)(?:\[(?P<k>\d+)\])?", object_path)
    if m_name:
        styles.append(_deprecated_names(m_name["model"], m_name["n"]))
        k = 0 if m_name["n"] is None else int(m_name["n"]) + 1
        styles.append(_alias_names(f"/{m_name['model']}[{k}]"))
    elif object_path.startswith("/"):
        styles.append(_alias_names(object_path))
        if m_path:
            k = int(m_path["k"] or 0)
            styles.append(_deprecated_names(m_path["model"], None if k == 0 else str(k - 1)))
    else:
        raise ValueError(
            f"robot object {object_path!r} is neither a V-REP name (ePuck, ePuck#0) "
            "nor an alias path (/ePuck, /ePuck[1])"
        )
    return styles


def _deprecated_names(model: str, n: str | None) -> dict[str, Any]:
    suffix = "" if n is None else f"#{n}"
    return {
        "base": model + suffix,
        "left": f"{model}_leftJoint{suffix}",
        "right": f"{model}_rightJoint{suffix}",
        "prox": [f"{model}_proxSensor{k}{suffix}" for k in range(1, 9)],
        "light": f"{model}_lightSensor{suffix}",
        "camera": f"{model}_camera{suffix}",
    }


def _alias_names(path: str) -> dict[str, Any]:
    return {
        "base": path,
        "left": f"{path}/leftJoint",
        "right": f"{path}/rightJoint",
        "prox": [(f"{path}/proxSensor", k) for k in range(8)],
        "light": f"{path}/lightSensor",
        "camera": f"{path}/camera",
    }


def show_name(name: Any) -> str:
    """A name of :func:`robot_object_names` as a message shows it."""
    return f"{name[0]} (index {name[1]})" if isinstance(name, tuple) else str(name)
