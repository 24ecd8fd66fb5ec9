"""The outcome of one episode: what the judge decided, in the form ``puckboard run --json`` prints.

It lives beside the judge, not with the control loop, because every way of running a
scene ends in one: an episode on any backend, the robot emulator's verdict on a client's
run, a sweep's rows. None of them needs to know how the others ran.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from .judge import Event, RobotMetrics

__all__ = ["EpisodeResult"]


@dataclass
class EpisodeResult:
    """The outcome of an episode; :meth:`to_dict` is the ``puckboard run --json`` object."""

    scenario: str
    controller: str
    seed: int
    dt_s: float
    steps: int
    sim_time_s: float
    wall_s: float
    success: bool
    failure: str | None
    robots: list[RobotMetrics] = field(default_factory=list)
    events: list[Event] = field(default_factory=list)
    #: every failure the judge detected, in order (``failure`` is the one reported)
    failures: list[str] = field(default_factory=list)
    #: the conditions ``--variation reality-gap`` drew (None, and not reported, otherwise)
    conditions: dict[str, Any] | None = None
    #: the control loop's period and latency (s) when they differ from one tick per
    #: step and no delay (``None``: today's synchronous loop, and no fields in the JSON)
    control_period_s: float | None = None
    control_latency_s: float | None = None
    #: how the loop varied cycle by cycle, when it did (``control.cycle_latency``,
    #: ``control.repeated``): the latency's median, 90th percentile and maximum (s) and
    #: the share of repeated readings; ``None``, and no field in the JSON, otherwise
    control_cycle: dict[str, float] | None = None

    @property
    def realtime_factor(self) -> float:
        """Simulated seconds per wall-clock second."""
        return self.sim_time_s / self.wall_s if self.wall_s > 0 else float("inf")

    def to_dict(self) -> dict[str, Any]:
        """Exactly the fields of ``puckboard run --json`` (JSON-serialisable); ``conditions``
        only when a variation drew them."""
        rtf = self.realtime_factor
        # the loop's timing only when it is not the default, so a default run's object
        # (and every figure published from one) stays what it was
        timing: dict[str, Any] = (
            {}
            if self.control_period_s is None
            else {
                "control_period_s": self.control_period_s,
                "control_latency_s": self.control_latency_s or 0.0,
            }
        )
        if self.control_cycle is not None:
            timing["control_cycle"] = dict(self.control_cycle)
        out: dict[str, Any] = {
            "scenario": self.scenario,
            "controller": self.controller,
            "seed": self.seed,
            "dt_s": self.dt_s,
            **timing,
            "steps": self.steps,
            "sim_time_s": round(self.sim_time_s, 6),
            "wall_s": round(self.wall_s, 6),
            "realtime_factor": round(rtf, 3) if math.isfinite(rtf) else None,
            "success": self.success,
            "failure": self.failure,
            "failures": list(self.failures),
            "robots": [m.to_dict() for m in self.robots],
            "events": [e.to_dict() for e in self.events],
        }
        if self.conditions is not None:
            out["conditions"] = self.conditions
        return out
