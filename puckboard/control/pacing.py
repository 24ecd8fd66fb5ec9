"""Pacing a simulated run to the wall clock, for people watching it.

A simulated run goes as fast as the machine allows: the two-robot pass takes about a
second. A table or a plot that updates that fast flashes past, so tools that are watched
(``puckboard monitor``) hold the simulation back to ``speed`` times real time. The run's
results do not change: pacing only waits between cycles, it never skips or repeats one.
Real robots keep their own pace, so a run that is not stepped is never held back.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .episode import Episode

__all__ = ["RealTimePacer"]


class RealTimePacer:
    """An episode observer that sleeps so simulation time runs at ``speed`` × real time.

    ``speed`` 1 is real time, 2 twice as fast; ``clock`` and ``sleep`` are injectable so
    the pacing can be checked without waiting.
    """

    def __init__(
        self,
        speed: float = 1.0,
        *,
        clock: Callable[[], float] | None = None,
        sleep: Callable[[float], None] | None = None,
    ) -> None:
        if not speed > 0:
            raise ValueError(f"speed must be a positive multiple of real time, got {speed}")
        self.speed = float(speed)
        self._clock = clock or time.perf_counter
        self._sleep = sleep or time.sleep
        self._start: tuple[float, float] | None = None  # (simulation time, wall time)

    def __call__(self, episode: Episode) -> None:
        if not getattr(episode.loop, "synchronous", False):
            return  # a real robot: its loop already keeps wall-clock time
        now_sim, now_wall = float(episode.time), self._clock()
        if self._start is None:
            self._start = (now_sim, now_wall)
            return
        sim0, wall0 = self._start
        ahead = (now_sim - sim0) / self.speed - (now_wall - wall0)
        if ahead > 0:
            self._sleep(ahead)
