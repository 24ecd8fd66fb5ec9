"""The simulation: start, pause, stop, its time and state, stepping, and log messages.

``sim.stopSimulation`` restores the scene's initial state and clears signals, as
CoppeliaSim does, so the next run starts from the same poses with the same seed.
Stepping (``sim.setStepping``/``sim.step``) only records what a client asks for here; the
server's stepping gate (:mod:`..clients`) decides when the world advances and finishes
the waiting ``sim.step`` calls.
"""

from __future__ import annotations

import logging
import time
from typing import Any

from ..clients import ClientState
from ..objects import DUMMY
from .names import CONSTANTS as _C
from .names import SIMULATION_ADVANCING_RUNNING, SIMULATION_PAUSED, SIMULATION_STOPPED
from .state import STEP_PENDING, ServedState

__all__ = ["SimulationFunctions"]

log = logging.getLogger(__name__)


class SimulationFunctions(ServedState):
    """``sim.start/pause/stopSimulation``, ``sim.getSimulation*``, ``sim.setStepping``,
    ``sim.step``, ``sim.addLog``; and the world's reset and advance for the server."""

    def get_simulation_time(self, client: ClientState) -> list[Any]:
        return [float(self.world.time)]

    def get_simulation_time_step(self, client: ClientState) -> list[Any]:
        return [float(self.world.dt)]

    def get_simulation_state(self, client: ClientState) -> list[Any]:
        if not self.running:
            return [SIMULATION_STOPPED]
        return [SIMULATION_PAUSED if self.paused else SIMULATION_ADVANCING_RUNNING]

    def get_system_time(self, client: ClientState) -> list[Any]:
        return [time.monotonic()]

    def start_simulation(self, client: ClientState) -> list[Any]:
        if not self.running or self.paused:
            log.info(
                "simulation %s by client %s", "resumed" if self.paused else "started", client.short
            )
        if not self.running:
            self.running = True
            self.world.start()
        self.paused = False
        return [1]

    def pause_simulation(self, client: ClientState) -> list[Any]:
        if not self.running:
            return [-1]  # CoppeliaSim: nothing to pause
        if not self.paused:
            self.paused = True
            log.info("simulation paused by client %s at t=%.2f s", client.short, self.world.time)
        return [1]

    def stop_simulation(self, client: ClientState, _wait: Any = None) -> list[Any]:
        """Stop and restore the initial scene (the server releases waiting clients)."""
        if self.running:
            log.info(
                "simulation stopped by client %s at t=%.2f s; scene restored",
                client.short,
                self.world.time,
            )
        self.running = False
        self.paused = False
        self.reset()
        return [1]

    @property
    def advancing(self) -> bool:
        """Running and not paused: the simulation may step."""
        return self.running and not self.paused

    def reset(self) -> None:
        self.world = self._world_class(self.scene, seed=self.seed)
        self.targets[:] = 0.0
        self._restore_scene_state()

    def _restore_scene_state(self) -> None:
        self.signals.clear()
        self.dummy_frames = {o.handle: o.local for o in self.objects if o.kind == DUMMY}

    def set_stepping(self, client: ClientState, enabled: bool) -> list[Any]:
        previous = client.stepping
        client.stepping = previous + 1 if enabled else max(0, previous - 1)
        if (previous > 0) != (client.stepping > 0):
            log.info(
                "client %s %s",
                client.short,
                "steps the simulation" if client.stepping else "no longer steps the simulation",
            )
        return [previous]

    def step(self, client: ClientState, _wait: Any) -> Any:
        """Wait for the next simulation step (:data:`STEP_PENDING`), as CoppeliaSim's add-on
        does for every client; a stepping client's request also lets the step happen.

        While the simulation is stopped (or paused) there is no step to wait for and
        ``sim.step`` returns at once, as in CoppeliaSim. A stepping client's loop that
        begins before the start therefore runs ahead of the others and may end, and leave,
        while they still wait for it: the first such call of each client is logged as a
        warning, with the way out."""
        client.steps += 1
        if not self.advancing:
            client.idle_steps += 1
            if client.stepping > 0 and not client.warned_idle_step:
                client.warned_idle_step = True
                log.warning(
                    "client %s steps, but called sim.step while the simulation is %s: "
                    "sim.step then returns at once (as in CoppeliaSim), so its loop runs "
                    "ahead of the simulation and of the other clients, and may end while "
                    "they still wait for it. Start the simulation before the loop, or wait "
                    "until sim.getSimulationState() is no longer sim.simulation_stopped "
                    "(docs/coppeliasim.md, 'A class of stepping clients')",
                    client.short, "paused" if self.running else "stopped",
                )  # fmt: skip
            return []
        client.desired_step = self.world.step_count + 1
        client.waiting = True
        return STEP_PENDING

    def advance(self) -> None:
        """One simulation step (the server calls this when the stepping gate opens)."""
        self.world.step(1)

    @property
    def step_count(self) -> int:
        return int(self.world.step_count)

    def add_log(self, client: ClientState, verbosity: int, message: str) -> list[Any]:
        level = logging.WARNING if verbosity <= _C.get("verbosity_warnings", 300) else logging.INFO
        log.log(level, "client %s: %s", client.short, message)
        return []

    def add_statusbar_message(self, client: ClientState, message: str) -> list[Any]:
        log.info("client %s: %s", client.short, message)
        return []
