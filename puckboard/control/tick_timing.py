"""Which layer makes a controller slower than its control period, said once per robot.

A controller whose tick takes longer than the control period cannot keep up: in
simulation the run slows below real time, on a robot the cycles overrun. Without a word
the user sees only "0.12x real time" and cannot tell which of their layers is slow. The
loop times every controller tick (two clock reads); after the first tick longer than
the period, the next tick is run with every layer's ``observe``, ``applies`` and
``command`` timed (what a layer's own code spends), and one warning names the slowest
layer and its time per tick.

The layers are timed where the controller calls them (``Controller.tick`` for
``observe``, each layer's node for ``applies`` and ``command``), for that one tick
(:meth:`~puckboard.behaviours.Controller.time_layers`); the ticks before and after run
the untimed code, which pays nothing for the timing. The student's layer objects are
never touched, and the calls, their order and the run are the same.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

__all__ = ["TickTimer"]

log = logging.getLogger(__name__)


class TickTimer:
    """Per robot: times its controller's ticks against ``period`` (seconds) and warns
    once, naming the slowest layer, when they take longer."""

    # Any: the loop runs any object with tick(ns), not only a Controller (timed whole)
    def __init__(self, robot: str, controller: Any, period: float) -> None:
        self.robot = robot
        self.controller = controller
        self.period = period
        self._slow_tick: float | None = None  # the first tick over the period, seconds
        self._done = False

    @contextmanager
    def tick(self) -> Iterator[None]:
        """Time one tick of the controller (the body ticks it)."""
        if self._done:
            yield
            return
        if self._slow_tick is None:
            t0 = time.perf_counter()
            yield
            elapsed = time.perf_counter() - t0
            if elapsed > self.period:
                self._slow_tick = elapsed
            return
        spent: dict[str, float] = {}
        with _timed_layers(self.controller, spent):
            yield
        self._done = True
        self._warn(spent)

    def _warn(self, spent: dict[str, float]) -> None:
        name = getattr(self.controller, "name", "controller")
        slow = self._slow_tick or 0.0
        if spent:
            layer, seconds = max(spent.items(), key=lambda item: item[1])
            blame = f"its slowest layer, {layer}, takes {seconds * 1e3:.0f} ms per tick"
        else:
            blame = "no layer of it was timed"
        log.warning(
            "robot %r: a tick of controller %r took %.0f ms, longer than the %.0f ms control "
            "period, so the run goes slower than real time; %s",
            self.robot, name, slow * 1e3, self.period * 1e3, blame,
        )  # fmt: skip


@contextmanager  # Any: as TickTimer's controller, any object with tick(ns)
def _timed_layers(controller: Any, spent: dict[str, float]) -> Iterator[None]:
    """Within the block the controller adds each layer's seconds to ``spent[layer name]``
    (:meth:`~puckboard.behaviours.Controller.time_layers`; a controller of another kind
    is timed as a whole only)."""
    time_layers = getattr(controller, "time_layers", None)
    if time_layers is None:
        yield
        return
    time_layers(spent, time.perf_counter)
    try:
        yield
    finally:
        time_layers(None)
