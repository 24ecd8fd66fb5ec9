"""What a layer is handed for one tick: the frame it reads and where its decision goes.

A :class:`~puckboard.behaviours.Controller` makes one :class:`TickContext` and hands it
to every behaviour of its tree when the tree is set up (py_trees passes the keyword
arguments of ``setup`` to every node: ``context=...``). At each tick the controller puts
a fresh :class:`Frame` in it; the layer that gets the wheels leaves its proposal there,
and a layer that raises leaves its name, so an error report can say which layer it was.
This module is all that layers and decorators share with the controller: they never
see the controller itself.
"""

from __future__ import annotations

import reprlib
from dataclasses import dataclass
from typing import Any

from ..blackboard import Snapshot
from ..errors import LayerError, NonFiniteError
from ..records import Ground, Proximity, WheelCommand

__all__ = ["Frame", "TickContext"]


class Frame:
    """What the layers see during one tick: a snapshot plus convenient typed accessors.

    Missing or stale values read as ``None``; a layer decides what that means (the
    source controllers treat "ground not updated" as "no line").
    """

    __slots__ = ("snapshot", "time")

    def __init__(self, snapshot: Snapshot) -> None:
        self.snapshot = snapshot
        self.time = snapshot.now

    def value(self, key: str, default: Any = None) -> Any:
        """The fresh value of ``key``, else ``default``."""
        return self.snapshot.value(key, default)

    @property
    def proximity(self) -> Proximity | None:
        return self.snapshot.value("proximity")  # type: ignore[no-any-return]

    @property
    def ground(self) -> Ground | None:
        return self.snapshot.value("ground")  # type: ignore[no-any-return]


@dataclass(eq=False)
class TickContext:
    """One controller's tick, shared with the behaviours of its tree (see the module)."""

    #: The snapshot of the current tick (``None`` before the first tick).
    frame: Frame | None = None
    #: ``(layer name, wheel command)`` of the layer that took the wheels this tick.
    proposal: tuple[str, WheelCommand] | None = None
    #: The layer whose ``observe``, ``applies`` or ``command`` raised during this tick.
    failed_layer: str | None = None

    def begin(self, frame: Frame) -> None:
        """Start a tick: a new frame, no proposal and no failure yet."""
        self.frame = frame
        self.proposal = None
        self.failed_layer = None

    def propose(self, layer: str, command: object) -> None:
        """``layer`` takes the wheels with ``command``, which must be a WheelCommand."""
        if not isinstance(command, WheelCommand):
            self.failed_layer = layer
            raise LayerError(_not_a_command(command), layer)
        self.proposal = (layer, command)

    def blame(self, layer: str, exc: Exception) -> LayerError | None:
        """Note that ``layer`` raised ``exc``. Returns the :class:`LayerError` to raise in
        its place when puckboard refused what the layer did (a speed that is not a
        finite number), ``None`` when the error is the layer's own code's."""
        self.failed_layer = layer
        if isinstance(exc, NonFiniteError):
            return LayerError(str(exc), layer)
        return None


_WANTED = "it must return WheelCommand(left, right), the wheel speeds in rad/s"


def _not_a_command(value: object) -> str:
    """What was wrong with a ``command()`` result, and what to return instead."""
    if value is None:
        return f"command() returned None (is a 'return' missing?); {_WANTED}"
    return f"command() returned {reprlib.repr(value)}, a {type(value).__name__}; {_WANTED}"
