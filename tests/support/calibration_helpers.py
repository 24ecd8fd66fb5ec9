"""A robot whose IR sensors are known to differ, for the calibration's tests.

The gains and offsets are chosen to be unlike the table and unlike each other: gains
across the plausible 0.7-1.3, offsets of both signs (a negative one reads 0 far from the
wall, so only the wall's readings tell it), one of them 0.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

from puckboard.profile import EPUCK, RobotProfile, apply_overrides
from puckboard.records import PROX_NAMES

KNOWN_GAINS = dict(zip(PROX_NAMES, (0.85, 1.2, 0.75, 1.1, 0.9, 1.25, 0.8, 1.05)))
KNOWN_OFFSETS = dict(zip(PROX_NAMES, (12.0, -6.0, 20.0, 0.0, 8.0, -10.0, 30.0, 4.0)))


def known_overrides(**changes: float) -> dict[str, float]:
    """The known robot's gains and offsets as profile paths, with ``changes`` (path with
    ``__`` for ``.``: ``ir_offset__right=-4000``) on top."""
    values = {f"ir_gain.{k}": v for k, v in KNOWN_GAINS.items()}
    values |= {f"ir_offset.{k}": v for k, v in KNOWN_OFFSETS.items()}
    values |= {k.replace("__", "."): v for k, v in changes.items()}
    return values


def known_profile(**changes: float) -> RobotProfile:
    return apply_overrides(EPUCK, known_overrides(**changes), source="known for the test")


def write_known_file(folder: Path, **changes: float) -> Path:
    """The known robot as a profile file, the way a user gives one to ``emulate``."""
    path = folder / "known.toml"
    lines = ['base = "epuck"', 'name = "known"', 'source = "known for the test"', "", "[set]"]
    lines += [f'"{path}" = {value!r}' for path, value in known_overrides(**changes).items()]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def wall_robot(actual: RobotProfile | None, *, seed: int = 0, **spec: Any) -> Any:
    """The ``calibration-wall`` scene in the embedded simulator, its robot built as
    ``actual`` (believing it is ``epuck``); ``spec`` changes the robot's start (x, y ...)
    or the scene (``obstacles=...``). Returns the connection."""
    from puckboard.backends.embedded import open_embedded
    from puckboard.scenario.scenefile import load_scene

    scene = load_scene("calibration-wall")
    scene_changes = {k: spec.pop(k) for k in ("obstacles", "noise") if k in spec}
    robot = dataclasses.replace(scene.robots[0], actual=actual, **spec)
    scene = dataclasses.replace(scene, robots=(robot,), **scene_changes)
    return open_embedded(scene, seed=seed)
