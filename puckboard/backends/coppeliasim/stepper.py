"""RemoteStepper: the remote simulation advanced one ``sim.step()`` per control cycle.

CoppeliaSim's stepping mode makes the simulation wait for every stepping client, so a
controller on the other end of a socket is as synchronous as the embedded one: each
cycle senses, commands and then lets exactly one step happen. All robots on one
:class:`~.link.RemoteLink` share one stepper, so a cycle is one ``sim.step`` whatever the
number of robots.
"""

from __future__ import annotations

import logging

from ..base import Stepper
from .link import RemoteLink

__all__ = ["RemoteStepper"]

log = logging.getLogger(__name__)


class RemoteStepper(Stepper):
    """The remote simulation in stepping mode: ``sim.setStepping(True)`` once, then one
    ``sim.step()`` per step. Shared by every robot on the same :class:`RemoteLink`.

    ``time`` is simulation time as last known: counted from completed steps and corrected
    by every sense-all reply (which carries the simulation time).
    """

    def __init__(self, link: RemoteLink, *, dt: float | None = None) -> None:
        self.link = link
        self._dt = dt
        self._time = 0.0
        self.stepping = False

    @property
    def dt(self) -> float:
        if self._dt is None:
            self._dt = float(self.link.call("sim.getSimulationTimeStep"))
        return self._dt

    @property
    def time(self) -> float:
        return self._time

    def note_time(self, t: float) -> None:
        self._time = float(t)

    def start(self) -> None:
        if not self.stepping:
            self.link.call("sim.setStepping", [True])
            self.stepping = True
        self.link.call("sim.startSimulation")
        self._time = float(self.link.call("sim.getSimulationTime"))

    def step(self, n: int = 1) -> None:
        if n < 0:
            raise ValueError(f"cannot step a negative number of times ({n})")
        dt = self.dt
        for _ in range(n):
            self.link.call("sim.step")
            self._time += dt

    def stop(self) -> None:
        """Stop the simulation (CoppeliaSim restores the scene; stepping ends)."""
        self.link.call("sim.stopSimulation")
        self.stepping = False

    def release(self, *, stop: bool = False) -> None:
        """Leave stepping mode (so others are not held back), optionally stopping; never raises."""
        try:
            if stop:
                self.stop()
            elif self.stepping:
                self.link.call("sim.setStepping", [False])
                self.stepping = False
        except Exception as exc:
            log.debug("releasing the remote simulation: %s", exc)
