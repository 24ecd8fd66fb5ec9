"""What a layer is handed for one tick: the frame it reads and where its decision goes.

A :class:`~puckboard.behaviours.Controller` makes one :class:`TickContext` and hands it
to every behaviour of its tree when the tree is set up (py_trees passes the keyword
arguments of ``setup`` to every node: ``context=...``). At each tick the controller puts
the tick's snapshot in it; the layer that gets the wheels leaves its proposal there,
and a layer that raises leaves its name, so an error report can say which layer it was.
This module is all that layers and decorators share with the controller: they never
see the controller itself.

Each layer reads through a :class:`Frame` of its own, made once when the tree is set up
and pointed at each tick's snapshot: a frame that knows the layer's ``reads`` can refuse
a key the layer never declared, where one snapshot of every layer's keys would hand it
another layer's value or, for a misspelt key, a silent ``None`` for ever.
"""

from __future__ import annotations

import difflib
import reprlib
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

from ..blackboard import Snapshot
from ..errors import LayerError, NonFiniteError
from ..records import Ground, Proximity, Sensor, WheelCommand

__all__ = ["Frame", "TickContext"]

#: Keys every robot may have whatever its backend: its sensors and its commands.
ROBOT_KEYS = frozenset([*(sensor.key for sensor in Sensor), "command/wheels", "command/layer"])


class Frame:
    """What the layers see during one tick: a snapshot plus convenient typed accessors.

    Missing or stale values read as ``None``; a layer decides what that means (the
    source controllers treat "ground not updated" as "no line"). A layer's own frame
    (see :meth:`for_layer`) lets it read only the keys it declares in ``reads``.

    A controller hands a layer the same frame object at every tick, pointed at that
    tick's snapshot: keep the values a layer wants to remember, not the frame.
    """

    __slots__ = ("_declared", "_layer", "_reads", "snapshot", "time")

    def __init__(self, snapshot: Snapshot) -> None:
        self.snapshot = snapshot
        self.time: float = snapshot.now
        self._reads: frozenset[str] | None = None  # None: every key of the snapshot
        self._declared: tuple[str, ...] = ()
        self._layer = ""

    @classmethod
    def for_layer(cls, layer: str, reads: Iterable[str], snapshot: Snapshot) -> Frame:
        """A frame that refuses every key but ``reads``, naming ``layer`` when it does."""
        frame = cls(snapshot)
        frame._declared = tuple(reads)
        frame._reads = frozenset(frame._declared)
        frame._layer = layer
        return frame

    def point_at(self, snapshot: Snapshot) -> None:
        """Show ``snapshot`` from now on (the controller does this once per tick)."""
        self.snapshot = snapshot
        self.time = snapshot.now

    def value(self, key: str, default: Any = None) -> Any:
        """The fresh value of ``key``, else ``default``; a layer's frame refuses a key
        the layer does not declare in ``reads`` (:class:`~puckboard.errors.LayerError`)."""
        reads = self._reads
        if reads is not None and key not in reads:
            raise LayerError(_undeclared(key, self._declared), self._layer)
        return self.snapshot.value(key, default)

    @property
    def proximity(self) -> Proximity | None:
        return self.value("proximity")  # type: ignore[no-any-return]

    @property
    def ground(self) -> Ground | None:
        return self.value("ground")  # type: ignore[no-any-return]

    def __getattr__(self, name: str) -> Any:
        """Only for a name the frame does not have (``frame.proximty``): Python's own
        message would not say what was meant; this one does, and how to read any key."""
        public = [n for n in dir(type(self)) if not n.startswith("_")]
        close = difflib.get_close_matches(name, public, n=1)
        meant = f"; did you mean frame.{close[0]}?" if close else ""
        raise AttributeError(
            f"a Frame has no attribute {name!r}{meant} (frame.value('KEY') reads any key the "
            "layer declares in reads)",
            name=name,
            obj=self,
        )


def _undeclared(key: str, declared: tuple[str, ...]) -> str:
    """Why a layer may not read ``key``, what it declares, and what it may have meant."""
    known = [*declared, *sorted(ROBOT_KEYS.difference(declared))]
    close = difflib.get_close_matches(key, known, n=1)
    meant = close[0] if close and key not in ROBOT_KEYS else None  # a misspelt key
    text = f"reads {key!r}, which it does not declare in reads = {declared!r}"
    if meant is not None:
        text += f" (did you mean {meant!r}?)"
    if meant is None or meant not in declared:
        text += f"; to read it, add it: reads = {(*declared, meant or key)!r}"
    return text


@dataclass(eq=False)
class TickContext:
    """One controller's tick, shared with the behaviours of its tree (see the module)."""

    #: The whole snapshot of the current tick, every layer's keys (``None`` before the
    #: first tick); the layers themselves read through frames of their own.
    frame: Frame | None = None
    #: ``(layer name, wheel command)`` of the layer that took the wheels this tick.
    proposal: tuple[str, WheelCommand] | None = None
    #: The layer whose ``observe``, ``applies`` or ``command`` raised during this tick.
    failed_layer: str | None = None

    def begin(self, snapshot: Snapshot) -> Frame:
        """Start a tick: its snapshot, no proposal and no failure yet. Returns the
        whole frame (one object for the controller's life, pointed at each snapshot)."""
        frame = self.frame
        if frame is None:
            frame = self.frame = Frame(snapshot)
        else:
            frame.point_at(snapshot)
        self.proposal = None
        self.failed_layer = None
        return frame

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


def current_frame(context: TickContext | None, behaviour: str) -> Frame:
    """The tick's frame from ``context``: the one check that a behaviour of puckboard's
    runs inside a Controller's tick (py_trees could tick it in a tree of its own, where
    nobody takes a snapshot)."""
    frame = context.frame if context is not None else None
    if frame is None:
        raise RuntimeError(
            f"{behaviour!r} was ticked outside a Controller; build a Controller from your "
            "layers and call controller.tick()"
        )
    return frame


_WANTED = "it must return WheelCommand(left, right), the wheel speeds in rad/s"


def _not_a_command(value: object) -> str:
    """What was wrong with a ``command()`` result, and what to return instead."""
    if value is None:
        return f"command() returned None (is a 'return' missing?); {_WANTED}"
    return f"command() returned {reprlib.repr(value)}, a {type(value).__name__}; {_WANTED}"
