"""A behaviour layer: an activation condition and an action, as a py_trees behaviour.

In Brooks' subsumption architecture every layer is a complete little controller that
wants the wheels under some condition; a fixed priority decides which one gets them.
A :class:`Layer` says three things:

* ``reads``: the blackboard keys it looks at (relative to the robot's namespace);
* ``applies(frame)``: whether it wants control now;
* ``command(frame)``: the wheel speeds it wants (rad/s).

Inside the tree a layer that applies returns ``RUNNING`` and proposes its command; one
that does not returns ``FAILURE`` and the arbiter (a Selector without memory) asks the
next layer down. A layer never talks to an adapter: it sees a :class:`Frame`, a
consistent snapshot of the blackboard taken once at the start of the tick, so all the
values behind one decision describe the same instant.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, ClassVar

import py_trees
import py_trees.logging
from py_trees.common import Status

from ..blackboard import Snapshot
from ..records import Ground, Proximity, WheelCommand

if TYPE_CHECKING:
    from .controller import Controller

__all__ = ["Frame", "Layer"]

# Public attributes py_trees sets on every behaviour: bookkeeping, not tunable parameters.
_PY_TREES_ATTRIBUTES = frozenset(
    ("name", "id", "status", "feedback_message", "blackbox_level", "qualified_name")
)


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


class Layer(py_trees.behaviour.Behaviour):
    """Base class of behaviour layers; subclass and implement ``applies`` and ``command``."""

    #: Blackboard keys (relative to the robot's namespace) this layer reads.
    reads: ClassVar[tuple[str, ...]] = ()

    def __init__(self, name: str | None = None) -> None:
        super().__init__(name or type(self).__name__)
        self.controller: Controller | None = None

    def setup(self, **kwargs: Any) -> None:
        """py_trees hands every behaviour the controller when the tree is set up."""
        self.controller = kwargs.get("controller")

    # -- what subclasses write -------------------------------------------------------------
    def applies(self, frame: Frame) -> bool:
        """Whether this layer wants the wheels now. Default: always."""
        return True

    def command(self, frame: Frame) -> WheelCommand:
        """The wheel speeds (rad/s) this layer wants."""
        raise NotImplementedError(f"{type(self).__name__} must implement command(frame)")

    # -- py_trees plumbing -----------------------------------------------------------------
    def update(self) -> Status:
        ctrl = self.controller
        if ctrl is None or ctrl.frame is None:
            raise RuntimeError(
                f"layer {self.name!r} was ticked outside a Controller; build a Controller "
                "from your layers and call controller.tick()"
            )
        frame = ctrl.frame
        try:
            if not self.applies(frame):
                return Status.FAILURE
            ctrl.propose(self, self.command(frame))
        except Exception:
            ctrl.failed_layer = self.name  # so the error report can say which layer raised
            raise
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
