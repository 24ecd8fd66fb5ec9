"""A behaviour layer: an activation condition and an action, as a py_trees behaviour.

In Brooks' subsumption architecture every layer is a complete little controller that
wants the wheels under some condition; a fixed priority decides which one gets them.
A :class:`Layer` says up to four things:

* ``reads``: the blackboard keys it looks at (relative to the robot's namespace);
* ``observe(frame)``: what it notes at every tick, whichever layer drives (optional);
* ``applies(frame)``: whether it wants control now;
* ``command(frame)``: the wheel speeds it wants (rad/s).

Inside the tree a layer that applies returns ``RUNNING`` and proposes its command; one
that does not returns ``FAILURE`` and the arbiter (a Selector without memory) asks the
next layer down. The arbiter stops asking at the first layer that applies, so while a
higher layer drives, ``applies`` and ``command`` of the layers below it are not called
at all; ``observe`` is, on every layer at every tick, before the arbiter asks anyone.
That is where a layer keeps what it remembers (on which side the line was last seen,
say): in Brooks' machines every layer runs all the time, and suppression acts only on
what a layer *outputs*.

A layer never talks to an adapter or to the controller: it is handed a
:class:`~puckboard.behaviours.context.TickContext` when the tree is set up and reads the
tick's :class:`Frame` from it, a consistent snapshot of the blackboard taken once at the
start of the tick, so all the values behind one decision describe the same instant.
"""

from __future__ import annotations

from typing import Any, ClassVar

import py_trees
import py_trees.logging
from py_trees.common import Status

from ..errors import LayerError
from ..records import WheelCommand
from .context import Frame, TickContext

__all__ = ["Frame", "Layer", "require_initialised"]

# Public attributes py_trees sets on every behaviour: bookkeeping, not tunable parameters.
_PY_TREES_ATTRIBUTES = frozenset(
    ("name", "id", "status", "feedback_message", "blackbox_level", "qualified_name")
)


def require_initialised(behaviour: py_trees.behaviour.Behaviour) -> None:
    """Refuse a behaviour whose ``__init__`` never called ``super().__init__()``.

    py_trees would fail later, deep inside the tree, with "object has no attribute
    'parent'", which names neither the layer nor the fix.
    """
    if not hasattr(behaviour, "parent"):
        cls = type(behaviour).__name__
        raise LayerError(
            f"{cls}.__init__ never calls super().__init__(); add super().__init__() as the "
            f"first line of {cls}.__init__",
            cls,
        )


class Layer(py_trees.behaviour.Behaviour):
    """Base class of behaviour layers; subclass and implement ``applies`` and ``command``
    (and ``observe`` for a layer that must notice things while others drive)."""

    #: Blackboard keys (relative to the robot's namespace) this layer reads.
    reads: ClassVar[tuple[str, ...]] = ()

    def __init__(self, name: str | None = None) -> None:
        super().__init__(name or type(self).__name__)
        self.context: TickContext | None = None

    def setup(self, **kwargs: Any) -> None:
        """py_trees hands every behaviour the controller's tick context at tree setup."""
        self.context = kwargs.get("context")

    # -- what subclasses write -------------------------------------------------------------
    def observe(self, frame: Frame) -> None:
        """Called at every tick before any layer is asked, whether or not this one will
        be asked or will drive: update what the layer remembers. Default: nothing."""

    def applies(self, frame: Frame) -> bool:
        """Whether this layer wants the wheels now. Default: always."""
        return True

    def command(self, frame: Frame) -> WheelCommand:
        """The wheel speeds (rad/s) this layer wants."""
        raise NotImplementedError(f"{type(self).__name__} must implement command(frame)")

    # -- py_trees plumbing -----------------------------------------------------------------
    def update(self) -> Status:
        context = self.context
        frame = context.frame if context is not None else None
        if context is None or frame is None:
            raise RuntimeError(
                f"layer {self.name!r} was ticked outside a Controller; build a Controller "
                "from your layers and call controller.tick()"
            )
        try:
            if not self.applies(frame):
                return Status.FAILURE
            command = self.command(frame)
        except Exception as exc:
            error = context.blame(self.name, exc)  # so the error report can name the layer
            if error is None:
                raise
            raise error from exc
        context.propose(self.name, command)
        return Status.RUNNING

    def parameters(self) -> dict[str, Any]:
        """The layer's tunable parameters (public attributes that are numbers or strings)."""
        return {
            k: v
            for k, v in vars(self).items()
            if not k.startswith("_")
            and isinstance(v, (int, float, str, bool, tuple))
            and k not in _PY_TREES_ATTRIBUTES
        }
