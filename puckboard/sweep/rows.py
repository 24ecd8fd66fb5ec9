"""One flat row per episode: what ``--out`` files hold and summaries are computed from.

``puckboard run --json`` gives a nested object (robots and events are lists). CSV and
Parquet want flat columns, so a row keeps the scalar fields as they are, adds
episode-level aggregates of the per-robot metrics (``progress_laps`` is the mean over
robots, ``collisions`` and ``obstacles_passed`` the sums), spreads each robot's metrics
into ``robot.<name>.<metric>`` columns (with its ``profile`` and, as JSON, its
``profile_values``), stores the event list as a JSON string, and
adds the sweep's own columns: ``key`` (the episode's identity), ``controller`` (the spec
as given), ``params`` (JSON) and one ``param.<name>`` column per parameter. An episode
that ended without a result is an *error row*: failure ``error``, the message in
``error`` and how it ended in ``error_kind`` (:data:`ERROR_KINDS`).

Rows read back from a CSV file are all strings; :class:`Outcome` parses the few fields
summaries need, so a resumed sweep summarises old and new episodes alike.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from .plan import EpisodeSpec

__all__ = ["ERROR_FAILURE", "ERROR_KINDS", "Outcome", "error_kind", "error_row", "result_row"]

#: ``failure`` of an episode that ended without a result (see :data:`ERROR_KINDS`).
ERROR_FAILURE = "error"

#: ``error_kind`` of an error row → what happened.
ERROR_KINDS: dict[str, str] = {
    "exception": "the controller or the simulation raised an exception",
    "timeout": "the episode ran past its wall-clock limit and was stopped",
    "exited": "the controller ended its process (sys.exit, os._exit)",
    "crashed": "the process running the episode was killed or crashed",
    "memory": "the process ran out of the memory it may use",
}

_SCALARS = ("dt_s", "steps", "sim_time_s", "wall_s", "realtime_factor")
_ROBOT_METRICS = (
    "progress_laps",
    "distance_m",
    "collisions",
    "on_line_fraction",
    "obstacles_passed",
    "passed_other",
    "profile",
)


def _identity(scenario: str, spec: EpisodeSpec) -> dict[str, Any]:
    params = spec.param_dict
    row: dict[str, Any] = {
        "key": spec.key(scenario),
        "scenario": scenario,
        "controller": spec.controller,
        "seed": spec.seed,
        "params": json.dumps(params, sort_keys=True),
    }
    for name, value in sorted(params.items()):
        row[f"param.{name}"] = value
    return row


def result_row(scenario: str, spec: EpisodeSpec, result: Mapping[str, Any]) -> dict[str, Any]:
    """Flatten ``EpisodeResult.to_dict()`` for ``spec`` into one row."""
    row = _identity(scenario, spec)
    row["success"] = bool(result.get("success"))
    row["failure"] = result.get("failure") or ""
    row["error"] = ""
    row["error_kind"] = ""
    for name in _SCALARS:
        row[name] = result.get(name)
    robots = list(result.get("robots") or [])
    progress = [float(r.get("progress_laps") or 0.0) for r in robots]
    row["progress_laps"] = sum(progress) / len(progress) if progress else 0.0
    row["distance_m"] = sum(float(r.get("distance_m") or 0.0) for r in robots)
    row["collisions"] = sum(int(r.get("collisions") or 0) for r in robots)
    row["obstacles_passed"] = sum(int(r.get("obstacles_passed") or 0) for r in robots)
    for robot in robots:
        name = robot.get("name", "?")
        for metric in _ROBOT_METRICS:
            if metric in robot:
                row[f"robot.{name}.{metric}"] = robot[metric]
        if robot.get("profile_values"):  # JSON: the numbers that make this robot this robot
            row[f"robot.{name}.profile_values"] = json.dumps(
                robot["profile_values"], separators=(",", ":")
            )
    events = list(result.get("events") or [])
    row["n_events"] = len(events)
    row["events"] = json.dumps(events, separators=(",", ":"))
    return row


def error_kind(exc: BaseException) -> str:
    """The :data:`ERROR_KINDS` name of how an episode that raised ``exc`` ended."""
    kind = getattr(exc, "kind", None)  # an EpisodeLost says how itself
    if isinstance(kind, str) and kind in ERROR_KINDS:
        return kind
    if type(exc).__name__ == "WallTimeExceeded":
        return "timeout"
    if isinstance(exc, MemoryError):
        return "memory"
    if isinstance(exc, SystemExit):
        return "exited"
    return "exception"


def error_row(scenario: str, spec: EpisodeSpec, exc: BaseException) -> dict[str, Any]:
    """A row for an episode that ended without a result: a failure named ``error``, of
    the kind :func:`error_kind` gives.

    When grading a class, one student's controller crashing must cost that student the
    episode, not stop everyone else's sweep.
    """
    row = _identity(scenario, spec)
    message = str(exc) if getattr(exc, "kind", None) else f"{type(exc).__name__}: {exc}"
    row.update(
        success=False,
        failure=ERROR_FAILURE,
        error=message,
        error_kind=error_kind(exc),
        progress_laps=0.0,
        distance_m=0.0,
        collisions=0,
        obstacles_passed=0,
        n_events=0,
        events="[]",
    )
    return row


def _as_bool(value: Any) -> bool:
    if isinstance(value, str):
        return value.strip().lower() in ("true", "1", "yes")
    return bool(value)


def _as_float(value: Any) -> float:
    if value is None or value == "":
        return 0.0
    number = float(value)
    return number if math.isfinite(number) else 0.0


@dataclass(frozen=True)
class Outcome:
    """The part of a row that summaries and rankings use, with proper types."""

    key: str
    controller: str
    params: tuple[tuple[str, Any], ...]
    seed: int
    success: bool
    failure: str
    progress_laps: float
    collisions: float
    #: how an ``error`` episode ended (:data:`ERROR_KINDS`); empty for the others
    error_kind: str = ""

    @classmethod
    def from_row(cls, row: Mapping[str, Any]) -> Outcome:
        params_text = row.get("params") or "{}"
        params = json.loads(params_text) if isinstance(params_text, str) else dict(params_text)
        failure = row.get("failure")
        success = _as_bool(row.get("success"))
        return cls(
            key=str(row["key"]),
            controller=str(row.get("controller", "")),
            params=tuple(sorted(params.items())),
            seed=int(float(row.get("seed") or 0)),
            success=success,
            failure="" if success or failure is None else str(failure),
            progress_laps=_as_float(row.get("progress_laps")),
            collisions=_as_float(row.get("collisions")),
            error_kind=str(row.get("error_kind") or ("exception" if row.get("error") else "")),
        )
