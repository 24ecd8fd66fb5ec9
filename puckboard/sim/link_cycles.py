"""A link that varies cycle by cycle, as the embedded world runs it.

The scene's :class:`~puckboard.scenario.scene.Control` may give a per-cycle latency
distribution and a share of repeated readings (a real link's,
:mod:`puckboard.profile.link_cycles`). Per robot, this draws

* each command's latency: the loop's fixed ``latency`` plus one draw of the
  distribution, rounded to whole physics steps; a command is due no earlier than the one
  before it (one connection delivers in order), so a slow reply holds every later
  command back and the wheels keep the last command they had, as a robot does while
  its host waits; when several are due at once, the newest turns the wheels;
* each cycle's freshness: a share ``repeated`` of the cycles bring no new packet, spread
  evenly (a robot that refreshes its packet every other cycle repeats every other
  reading, as the recording does), starting at a drawn phase; the first cycle is always
  fresh, since a run starts with the robot's first packet.

Every draw comes from a generator of the robot's own, seeded ``[seed, robot, LINK_STREAM]``:
the world's generator (noise, start jitter) draws exactly what it draws without it.
"""

from __future__ import annotations

import numpy as np

from ..scenario.scene import Control

__all__ = ["LINK_STREAM", "LinkCycleState"]

#: The third word of every link generator's seed (the ASCII of "LINK").
LINK_STREAM = 0x4C494E4B


class LinkCycleState:
    """Commands on their way and the readings' freshness, for ``n`` robots."""

    def __init__(self, control: Control, n: int, *, seed: int, dt: float) -> None:
        self._latency = control.cycle_latency
        self._fixed = float(control.latency)
        self._fresh_share = 1.0 - float(control.repeated)
        self._dt = float(dt)
        self._rng = [np.random.default_rng([int(seed), i, LINK_STREAM]) for i in range(n)]
        self._phase = [float(r.random()) for r in self._rng]
        self._first = [True] * n
        #: per robot, (due step, (left, right)) in the order given
        self.pending: list[list[tuple[int, tuple[float, float]]]] = [[] for _ in range(n)]
        self._last_due = [0] * n

    def send(self, i: int, step: int, command: tuple[float, float]) -> None:
        """Robot ``i``'s command, given at ``step``, on its way."""
        seconds = self._fixed
        if self._latency is not None:
            seconds += self._latency.at(float(self._rng[i].random()))
        due = max(step + round(seconds / self._dt), self._last_due[i])
        self._last_due[i] = due
        self.pending[i].append((due, command))

    def due(self, i: int, step: int) -> tuple[float, float] | None:
        """The newest of robot ``i``'s commands due at ``step`` (taken off the way)."""
        queue = self.pending[i]
        arrived = None
        while queue and queue[0][0] <= step:
            arrived = queue.pop(0)[1]
        return arrived

    def clear(self) -> None:
        """Nothing still on its way arrives (the wheels were stopped)."""
        for queue in self.pending:
            queue.clear()

    def fresh(self, i: int) -> bool:
        """Whether robot ``i``'s reading this cycle is a new packet."""
        if self._first[i]:
            self._first[i] = False
            return True
        self._phase[i] += self._fresh_share
        if self._phase[i] >= 1.0:
            self._phase[i] -= 1.0
            return True
        return False
