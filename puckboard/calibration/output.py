"""What a calibration gives: a profile file for ``--profile``, and its report.

The file is the one docs/profiles.md describes: a shipped ``base``, the robot's ``name``,
a default ``source`` saying when and how it was measured, and under ``[set]`` one
``ir_gain.<sensor>`` and one ``ir_offset.<sensor>`` per sensor, each with its own source:
the fit's value and standard error, the residuals' root mean square and the number of
poses, and where that sensor stops detecting a white wall straight ahead. Numbers the
profile the calibration started from had set (a body radius measured with a ruler, say)
are kept with their sources: they are part of the same robot.

``prox_max_distance`` is not set. It is where a robot's *software* stops believing its
readings (the value at that distance is the cut-off below which a reading means nothing),
the same for every sensor, while where each sensor stops detecting follows from its gain
and offset: with them in the profile, the simulator reproduces each sensor's detection
end by itself, and setting the cut-off from the data as well would count a weak sensor
twice. The detection ends are written into the sources, for people to read.

Ambient light (the e-puck's ``light`` record, 0 bright .. 4095 dark) is reported with the
fit: a change of more than :data:`AMBIENT_CHANGE` during the run, at sensors turned away
from the wall (where the wall does not shade them), is worth a warning, because the IR
readings move with ambient light (e-puck.org's IR page). It is not used in the fit.
"""

from __future__ import annotations

import dataclasses
import datetime
import json
import math
import sys
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..profile import RobotProfile, apply_overrides, get_profile, profile_from_data
from ..records import PROX_NAMES
from .fit import SensorFit
from .readings import Measurements
from .response import WallModel

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on 3.10 only
    import tomli as tomllib

__all__ = [
    "AMBIENT_CHANGE",
    "AmbientLight",
    "ambient_light",
    "calibrated_profile",
    "fit_source",
    "profile_file_text",
    "run_source",
]

#: A change of ambient light (raw) worth a warning: a tenth of the sensor's scale. A
#: chosen threshold, not a measured one: the e-puck.org IR page shows the readings move
#: with ambient light without saying by how much.
AMBIENT_CHANGE = 410.0
_CALIBRATED = ("ir_gain", "ir_offset")


def _toml_string(text: str) -> str:
    """A TOML basic string (JSON's escapes are TOML's)."""
    return json.dumps(text, ensure_ascii=False)


def _toml_number(value: float) -> str:
    return repr(float(value))


def fit_source(fit: SensorFit, when: datetime.date) -> str:
    """The source of one sensor's gain and offset: the fit, its quality, its detection end."""
    if fit.detection_end is None:
        reach = "its offset is above the cut-off: it always reads something"
    elif fit.detection_end <= 0.0:
        reach = "it does not detect a wall"
    else:
        reach = f"detects a white wall up to {fit.detection_end * 1000:.1f} mm straight ahead"
    return (
        f"puckboard calibrate ir, {when.isoformat()}: gain {fit.gain:.3f} ± {fit.gain_se:.3f}, "
        f"offset {fit.offset:.1f} ± {fit.offset_se:.1f} raw, residual RMS {fit.rms:.1f} raw "
        f"over {fit.points} poses; {reach}"
    )


def _kept(profile: RobotProfile) -> list[tuple[str, float, str]]:
    """The numbers ``profile`` set that a calibration keeps: all but gains and offsets."""
    return [
        (path, value, profile.sources.get(path, ""))
        for path, value in profile.overrides
        if path.partition(".")[0] not in _CALIBRATED
    ]


def calibrated_profile(
    started_from: RobotProfile,
    fits: Sequence[SensorFit],
    *,
    name: str,
    when: datetime.date,
) -> RobotProfile:
    """The profile the calibration found: ``started_from``'s shipped base with the
    numbers it set (but its gains and offsets) and the fitted gains and offsets."""
    base = get_profile(started_from.base or started_from.name)
    values: dict[str, Any] = {}
    sources: dict[str, str] = {}
    for path, value, source in _kept(started_from):
        values[path], sources[path] = value, source
    for fit in fits:
        text = fit_source(fit, when)
        for head, value in (("ir_gain", round(fit.gain, 4)), ("ir_offset", round(fit.offset, 1))):
            path = f"{head}.{fit.sensor}"
            values[path], sources[path] = value, text
    profile = apply_overrides(base, values, source=sources)
    return dataclasses.replace(profile, name=name)


def run_source(measurements: Measurements, when: datetime.date, where: str) -> str:
    """The file's default source: when, how and over what the robot was measured."""
    plan = measurements.plan
    mm = 1000.0
    return (
        f"measured with puckboard calibrate ir on {when.isoformat()} over {where}: a white "
        f"wall, {plan.stops} stops {plan.start_distance * mm:g}-"
        f"{(plan.start_distance + plan.backs[-1]) * mm:g} mm from it (centre to wall), "
        f"{plan.samples} readings per pose, {measurements.seconds:.0f} s"
    )


def profile_file_text(
    profile: RobotProfile, default_source: str, *, header: Sequence[str] = ()
) -> str:
    """``profile`` (from :func:`calibrated_profile`) as a profile file, checked: it reads
    back as the very same numbers."""
    lines = [f"# {line}" if line else "#" for line in header]
    lines += [
        f"base = {_toml_string(profile.base)}",
        f"name = {_toml_string(profile.name)}",
        f"source = {_toml_string(default_source)}",
        "",
        "[set]",
    ]
    calibrated = [(p, v) for p, v in profile.overrides if p.partition(".")[0] in _CALIBRATED]
    kept = [(p, v) for p, v in profile.overrides if p.partition(".")[0] not in _CALIBRATED]
    order = {name: i for i, name in enumerate(PROX_NAMES)}
    calibrated.sort(key=lambda pv: (order[pv[0].partition(".")[2]], pv[0]))
    for path, value in calibrated + kept:
        source = profile.sources.get(path, default_source)
        lines.append(
            f"{_toml_string(path)} = {{ value = {_toml_number(value)}, "
            f"source = {_toml_string(source)} }}"
        )
    text = "\n".join(lines) + "\n"
    back = profile_from_data(tomllib.loads(text), source="<calibration>")
    if dict(back.overrides) != dict(profile.overrides):  # pragma: no cover - a bug here
        raise AssertionError("the profile file does not read back as the calibration's numbers")
    return text


@dataclasses.dataclass(frozen=True)
class AmbientLight:
    """Ambient light over a run: per sensor the lowest and highest mean at poses where
    the wall was out of its reach (``None`` where the backend reports no ambient light)."""

    low: np.ndarray | None
    high: np.ndarray | None

    @property
    def reported(self) -> bool:
        return self.low is not None

    def changes(self) -> list[tuple[str, float, float]]:
        """(sensor, lowest, highest) for every sensor whose ambient changed by more than
        :data:`AMBIENT_CHANGE`."""
        if self.low is None or self.high is None:
            return []
        return [
            (name, float(lo), float(hi))
            for name, lo, hi in zip(PROX_NAMES, self.low, self.high)
            if hi - lo > AMBIENT_CHANGE
        ]

    def describe(self) -> str:
        if self.low is None or self.high is None:
            return "ambient light: not reported by this backend"
        lo, hi = float(np.nanmin(self.low)), float(np.nanmax(self.high))
        changed = self.changes()
        if not changed:
            return f"ambient light: {lo:.0f}-{hi:.0f} (0 bright .. 4095 dark), steady"
        worst = max(changed, key=lambda c: c[2] - c[1])
        return (
            f"warning: ambient light changed during the run ({worst[0]}: {worst[1]:.0f} to "
            f"{worst[2]:.0f}, 0 bright .. 4095 dark); the IR readings move with it: calibrate "
            "again in steady light (no sun, lamps not moved)"
        )

    def to_dict(self) -> dict[str, Any] | None:
        if self.low is None or self.high is None:
            return None
        return {
            "low": [float(v) for v in self.low],
            "high": [float(v) for v in self.high],
            "changed": [c[0] for c in self.changes()],
        }


def ambient_light(measurements: Measurements, model: WallModel) -> AmbientLight:
    """The run's :class:`AmbientLight`."""
    rows = [r for r in measurements.readings if r.ambient is not None]
    if not rows:
        return AmbientLight(None, None)
    ambient = np.array([r.ambient for r in rows])
    expected = np.array([model.expected(r.distance, r.heading) for r in rows])
    away = np.where(expected <= 0.5, ambient, np.nan)
    low = np.array([np.nanmin(c) if not np.all(np.isnan(c)) else math.nan for c in away.T])
    high = np.array([np.nanmax(c) if not np.all(np.isnan(c)) else math.nan for c in away.T])
    return AmbientLight(low, high)
