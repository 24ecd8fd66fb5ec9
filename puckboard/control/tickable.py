"""What a control loop ticks: the :class:`Tickable` protocol.

A :class:`~puckboard.behaviours.Controller` is the one shipped, and every robot of a
:class:`~puckboard.control.loop.ControlLoop` is bound to one; the loop asks for no more
than this protocol, so it is written down once and type-checked, not reached for by name.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

from ..blackboard import Namespace
from ..records import WheelCommand

__all__ = ["Tickable"]


class Tickable(Protocol):
    """Decides one wheel command per control cycle from a robot's blackboard namespace."""

    @property
    def name(self) -> str:
        """What warnings and results call it."""
        ...

    @property
    def failed_layer(self) -> str | None:
        """The layer whose code raised during the last tick, if any (the loop's error
        report names it)."""
        ...

    def tick(self, ns: Namespace) -> WheelCommand:
        """Read ``ns``, decide, write the decision there and return the wheel command."""
        ...

    def time_layers(
        self, timings: dict[str, float] | None, clock: Callable[[], float] = ...
    ) -> None:
        """From the next tick on, add the seconds each layer takes to ``timings[layer
        name]``, read from ``clock``; ``None`` stops timing (see
        :mod:`puckboard.control.tick_timing`)."""
        ...
