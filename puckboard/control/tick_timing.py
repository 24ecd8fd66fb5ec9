"""Which layer makes a controller slower than its control period, said once per robot.

A controller whose tick takes longer than the control period cannot keep up: in
simulation the run slows below real time, on a robot the cycles overrun. Without a word
the user sees only "0.12x real time" and cannot tell which of their layers is slow. The
loop ticks every controller through its :class:`TickTimer` (two clock reads); after the
first tick longer than the period, the next tick is run with every layer's ``observe``,
``applies`` and ``command`` timed (what a layer's own code spends), and one warning
names the slowest layer and its time per tick.

The layers are timed for that one tick by the controller
(:meth:`~puckboard.control.tickable.Tickable.time_layers`: a py_trees visitor attached
to its tree, :class:`~puckboard.behaviours.layer_timing.LayerTiming`); the ticks before
and after run without it and pay nothing for the timing. The student's layer objects are
never touched, and the calls, their order and the run are the same.
"""

from __future__ import annotations

import logging
import time

from ..blackboard import Namespace
from ..records import WheelCommand
from .tickable import Tickable

__all__ = ["TickTimer"]

log = logging.getLogger(__name__)


class TickTimer:
    """Per robot: ticks its controller, timing the ticks against ``period`` (seconds),
    and warns once, naming the slowest layer, when they take longer."""

    def __init__(self, robot: str, controller: Tickable, period: float) -> None:
        self.robot = robot
        self.controller = controller
        self.period = period
        self._slow_tick: float | None = None  # the first tick over the period, seconds
        self._done = False

    def tick(self, ns: Namespace) -> WheelCommand:
        """Tick the controller on ``ns`` (timed, until the warning is given)."""
        if self._done:
            return self.controller.tick(ns)
        if self._slow_tick is None:
            t0 = time.perf_counter()
            command = self.controller.tick(ns)
            elapsed = time.perf_counter() - t0
            if elapsed > self.period:
                self._slow_tick = elapsed
            return command
        spent: dict[str, float] = {}
        self.controller.time_layers(spent, time.perf_counter)
        try:
            command = self.controller.tick(ns)
        finally:
            self.controller.time_layers(None)
        self._done = True
        self._warn(spent)
        return command

    def _warn(self, spent: dict[str, float]) -> None:
        slow = self._slow_tick or 0.0
        if spent:
            layer, seconds = max(spent.items(), key=lambda item: item[1])
            blame = f"its slowest layer, {layer}, takes {seconds * 1e3:.0f} ms per tick"
        else:
            blame = "no layer of it was timed"
        log.warning(
            "robot %r: a tick of controller %r took %.0f ms, longer than the %.0f ms control "
            "period, so the run goes slower than real time; %s",
            self.robot, self.controller.name, slow * 1e3, self.period * 1e3, blame,
        )  # fmt: skip
