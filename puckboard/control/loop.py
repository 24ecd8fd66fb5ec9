"""The control loop: sense → blackboard → tick → actuate → step, for one or more robots.

In a simulator the loop is *synchronous*: every robot senses at the same simulation
time, every controller decides, every wheel command is sent, then each world advances
one control period. Nothing depends on how fast the host is, so a run is reproducible.
On a real robot there is nothing to step: the loop keeps a fixed wall-clock period
instead and says so when it overruns.

Whatever ends a run (the duration, an exception in a layer, Ctrl-C), :meth:`ControlLoop.run`
commands every robot's wheels to zero, closes the adapters and tells the cycle
observers, so a recording is flushed and no robot drives on unattended.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass

from ..backends.base import RobotAdapter, Stepper
from ..records import Sensor
from .tick_timing import TickTimer
from .tickable import Tickable

__all__ = ["Binding", "ControlLoop", "ControllerFailure"]

log = logging.getLogger(__name__)

CycleObserver = Callable[["ControlLoop"], None]


@dataclass(frozen=True)
class ControllerFailure:
    """Where a controller raised: which robot, at what loop time (s), in which layer."""

    robot: str
    time: float
    layer: str | None

    def describe(self) -> str:
        where = f"in layer {self.layer!r}" if self.layer else "in its controller"
        return f"robot {self.robot!r} at t = {self.time:.2f} s, {where}"


@dataclass
class Binding:
    """One robot in the loop: its adapter and the controller that drives it."""

    adapter: RobotAdapter
    controller: Tickable


class ControlLoop:
    """Runs controllers against adapters; see the module docstring.

    ``period`` is the control period in seconds. In simulation it defaults to one
    simulation step and must be a whole number of steps; on a real robot it defaults to
    0.05 s. ``stale_after`` (default three periods) is the age at which a sensor value
    counts as stale for the controllers.
    """

    def __init__(
        self,
        bindings: Iterable[Binding | tuple[RobotAdapter, Tickable]],
        *,
        period: float | None = None,
        stale_after: float | None = None,
        camera_every: int = 0,
    ) -> None:
        self.bindings: list[Binding] = [
            b if isinstance(b, Binding) else Binding(*b) for b in bindings
        ]
        if not self.bindings:
            raise ValueError("a ControlLoop needs at least one (adapter, controller) pair")
        self.steppers: list[Stepper] = _unique(
            b.adapter.stepper for b in self.bindings if b.adapter.stepper is not None
        )
        if self.steppers and any(b.adapter.stepper is None for b in self.bindings):
            raise ValueError(
                "cannot mix simulated and real-time robots in one ControlLoop; run two loops"
            )
        self.synchronous = bool(self.steppers)
        if self.synchronous:
            dt = self.steppers[0].dt
            if any(abs(s.dt - dt) > 1e-12 for s in self.steppers):
                raise ValueError("all simulations in one ControlLoop need the same time step")
            self.period = dt if period is None else period
            ratio = self.period / dt
            if ratio < 1 - 1e-9 or abs(ratio - round(ratio)) > 1e-6:
                raise ValueError(
                    f"control period {self.period} s must be a whole number of simulation "
                    f"steps of {dt} s"
                )
            self.steps_per_cycle = round(ratio)
        else:
            self.period = 0.05 if period is None else period
            self.steps_per_cycle = 0
        if self.period <= 0:
            raise ValueError(f"control period must be positive seconds, got {self.period}")
        self.stale_after = 3 * self.period if stale_after is None else stale_after
        self.camera_every = camera_every
        self.cycles = 0
        #: where a controller raised, if one did (robot, time, layer)
        self.failure: ControllerFailure | None = None
        #: the run was stopped by Ctrl-C (close observers may want to say what they keep)
        self.interrupted = False
        self.overruns = 0
        self._timers: dict[str, TickTimer] = {}  # per robot: a controller slower than the period
        self.observers: list[CycleObserver] = []
        self.before_tick: list[CycleObserver] = []
        self.close_observers: list[CycleObserver] = []
        self._closed = False
        for b in self.bindings:
            b.adapter.set_stale_after(self.stale_after)

    # -- properties ------------------------------------------------------------------------
    @property
    def adapters(self) -> list[RobotAdapter]:
        return [b.adapter for b in self.bindings]

    @property
    def time(self) -> float:
        """Simulation time (synchronous) or seconds since the first cycle (real time)."""
        if self.synchronous:
            return self.steppers[0].time
        return time.monotonic() - self._t0 if hasattr(self, "_t0") else 0.0

    def add_observer(self, observer: CycleObserver) -> None:
        """``observer(loop)`` after every cycle (recorders, judges, live views)."""
        self.observers.append(observer)

    def add_before_tick(self, callback: CycleObserver) -> None:
        """``callback(loop)`` each cycle after sensing and before the controllers tick.

        This is where knowledge sources (filters, estimators) turn fresh sensor records
        into derived blackboard keys that the layers of the same tick can read.
        """
        self.before_tick.append(callback)

    def add_close_observer(self, observer: CycleObserver) -> None:
        """``observer(loop)`` once when the loop shuts down, however it ends."""
        self.close_observers.append(observer)

    # -- running ---------------------------------------------------------------------------
    def start(self) -> None:
        for stepper in self.steppers:
            stepper.start()
        self._t0 = time.monotonic()
        self._next = self._t0

    def cycle(self) -> None:
        """One control cycle for every robot."""
        if self.cycles == 0 and not hasattr(self, "_t0"):
            self.start()
        grab_camera = self.camera_every > 0 and self.cycles % self.camera_every == 0
        for b in self.bindings:
            b.adapter.sense_all()
            if grab_camera and Sensor.CAMERA in b.adapter.enabled_sensors:
                b.adapter.camera_image()
        for callback in self.before_tick:
            callback(self)
        for b in self.bindings:
            timer = self._timers.get(b.adapter.name)
            if timer is None:
                timer = self._timers[b.adapter.name] = TickTimer(
                    b.adapter.name, b.controller, self.period
                )
            try:
                cmd = timer.tick(b.adapter.ns)
            except Exception:
                # the exception goes on unchanged; this says where it happened, for the
                # one-line summary a command prints after the traceback
                layer = b.controller.failed_layer
                self.failure = ControllerFailure(b.adapter.name, self.time, layer)
                raise
            b.adapter.command_wheels(cmd)
        if self.synchronous:
            for stepper in self.steppers:
                stepper.step(self.steps_per_cycle)
        else:
            self._wait_for_next_period()
        self.cycles += 1
        for obs in self.observers:
            obs(self)

    def _wait_for_next_period(self) -> None:
        self._next += self.period
        delay = self._next - time.monotonic()
        if delay > 0:
            time.sleep(delay)
        else:
            self.overruns += 1
            if self.overruns in (1, 10, 100) or self.overruns % 1000 == 0:
                log.warning(
                    "control cycle overran its %.0f ms period by %.1f ms (%d overruns so far)",
                    self.period * 1e3, -delay * 1e3, self.overruns,
                )  # fmt: skip
            self._next = time.monotonic()

    def run(
        self,
        duration: float | None = None,
        *,
        cycles: int | None = None,
        until: Callable[[ControlLoop], bool] | None = None,
        close: bool = True,
    ) -> int:
        """Run for ``duration`` seconds (simulated or wall), ``cycles`` cycles, or until
        ``until(loop)`` is true; whichever comes first. Returns the cycles run.

        On any exception (Ctrl-C included) the wheels are zeroed and the adapters closed
        before the exception propagates. With ``close=True`` (the default) that also
        happens at the normal end.
        """
        if duration is None and cycles is None and until is None:
            raise ValueError("run() needs a duration, a number of cycles or an until() condition")
        max_cycles = math.inf if cycles is None else cycles
        if duration is not None:
            if duration < 0:
                raise ValueError(f"duration must be >= 0 seconds, got {duration}")
            max_cycles = min(max_cycles, math.ceil(duration / self.period - 1e-9))
        done = 0
        try:
            while done < max_cycles:
                self.cycle()
                done += 1
                if until is not None and until(self):
                    break
        except BaseException as exc:
            log.info("control loop stopping after an exception; zeroing wheels")
            self.interrupted = isinstance(exc, KeyboardInterrupt)
            self.close()
            raise
        if close:
            self.close()
        return done

    def stop_all(self) -> None:
        """Command every robot's wheels to zero (best effort, never raises)."""
        for b in self.bindings:
            if b.adapter.closed:
                continue
            try:
                b.adapter.stop_wheels()
            except Exception as exc:
                log.warning("could not stop robot %r: %s", b.adapter.name, exc)

    def close(self) -> None:
        """Zero the wheels, tell the close observers, close the adapters. Idempotent."""
        if self._closed:
            return
        self._closed = True
        self.stop_all()
        second_interrupt: KeyboardInterrupt | None = None
        for obs in self.close_observers:
            try:
                obs(self)
            except KeyboardInterrupt as exc:
                # Ctrl-C while finishing (a long animation): give up on that observer,
                # but the robots must still be closed
                second_interrupt = exc
                log.warning("interrupted while finishing up; closing the robots")
            except Exception:
                log.exception("control loop close observer %r failed", obs)
        for b in self.bindings:
            try:
                b.adapter.close()
            except Exception as exc:
                log.warning("could not close robot %r: %s", b.adapter.name, exc)
        if second_interrupt is not None:
            raise second_interrupt

    def __enter__(self) -> ControlLoop:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _unique(items: Iterable[Stepper]) -> list[Stepper]:
    out: list[Stepper] = []
    for item in items:
        if not any(item is o for o in out):
            out.append(item)
    return out
