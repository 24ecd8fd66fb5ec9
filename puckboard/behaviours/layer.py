"""A behaviour layer: an activation condition and an action, run by a py_trees behaviour.

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

A layer never talks to an adapter or to the controller: it reads the tick's
:class:`Frame`, a consistent snapshot of the blackboard taken once at the start of the
tick, so all the values behind one decision describe the same instant. Its frame shows
only the keys its ``reads`` declares: reading any other raises a
:class:`~puckboard.errors.LayerError` that names the layer, the key and the keys it
declared, where a snapshot of every layer's keys would answer ``None`` for a misspelt key
(and the layer would silently never apply) or another layer's value for a forgotten one.

A layer is *not* itself a py_trees behaviour: it owns one (:func:`as_behaviour`), which
the tree ticks and which calls the layer. py_trees behaviours carry many plain names
(``stop``, ``setup``, ``update``, ``status``, ``parent``, ``id``, ``tick``,
``iterate`` ...) that the tree calls; a layer of its own keeps those free, so a helper
method a student names ``stop`` is the student's, not a hook the tree calls with other
arguments. A layer's namespace holds ``name``, ``reads``, ``observe``, ``applies``,
``command``, ``reset`` and ``parameters``; everything else on it is its author's.

What py_trees calls ``initialise`` and ``terminate`` (a behaviour starting and ending a
run of ticks) a layer meets as one hook, ``reset()``: the controller starts afresh (a new
episode, the robot put back at its start) and the layer forgets what it remembers. Being
pre-empted by a higher layer is not a reset: a layer keeps observing while suppressed.

The node checks what the layer hands back: ``applies`` must return a bool (``None``, a
missing ``return``, would read as "never"; ``"no"`` as "always"), ``command`` a
:class:`~puckboard.records.WheelCommand`; either mistake is a
:class:`~puckboard.errors.LayerError` naming the layer and the fix.
"""

from __future__ import annotations

import reprlib
from typing import Any, ClassVar

import numpy as np
import py_trees
from py_trees.common import Status

from ..blackboard import Snapshot
from ..errors import LayerError
from ..records import WheelCommand
from .context import Frame, TickContext, current_frame

__all__ = ["Frame", "Layer", "LayerNode", "as_behaviour", "layer_node", "layer_of"]

#: What a layer's frame shows until the controller's first tick points it at a snapshot.
_NO_SNAPSHOT = Snapshot({}, {}, 0.0)


class Layer:
    """Base class of behaviour layers; subclass and implement ``applies`` and ``command``
    (and ``observe`` for a layer that must notice things while others drive).

    ``observe``, ``applies`` and ``command`` are handed the layer's own :class:`Frame`,
    which reads only the keys in ``reads``. In a controller built with ``requires=``, no
    layer is called, ``observe`` included, until every required key is fresh: the robot
    stands still meanwhile, so a layer never has to ask whether a required reading has
    arrived yet (``frame.proximity`` is a reading, never ``None``, in a controller that
    requires ``proximity``). Without ``requires=``, a key not read yet is ``None``.
    """

    #: Blackboard keys (relative to the robot's namespace) this layer reads.
    reads: ClassVar[tuple[str, ...]] = ()

    def __init__(self, name: str | None = None) -> None:
        self.__node = LayerNode(self, name or type(self).__name__)

    @property
    def name(self) -> str:
        """The layer's name: in ``command/layer``, traces, ``--set layer.NAME.attr=``."""
        return self.__node.name

    @name.setter
    def name(self, value: str) -> None:
        self.__node.name = value

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

    def reset(self) -> None:
        """Forget what the layer remembers, as if it had just been built: called by
        :meth:`Controller.reset <puckboard.behaviours.Controller.reset>` when the robot
        starts afresh. Override it in a layer that keeps state between ticks (the side
        the line was last seen on, say). Default: nothing."""

    def parameters(self) -> dict[str, Any]:
        """The layer's tunable parameters (public attributes that are numbers or strings)."""
        return {
            k: v
            for k, v in vars(self).items()
            if not k.startswith("_") and isinstance(v, (int, float, str, bool, tuple))
        }

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.name!r}>"


class LayerNode(py_trees.behaviour.Behaviour):
    """The py_trees behaviour that runs one :class:`Layer` in a tree.

    It returns ``RUNNING`` and proposes the layer's command when the layer applies,
    ``FAILURE`` when it does not. Its name is the layer's; ``reads`` are the layer's.
    """

    def __init__(self, layer: Layer, name: str) -> None:
        super().__init__(name)
        self.layer = layer
        self.context: TickContext | None = None
        #: The layer's own frame: made once, pointed at each tick's snapshot.
        self.frame = Frame.for_layer(name, (), _NO_SNAPSHOT)

    @property
    def reads(self) -> tuple[str, ...]:
        return self.layer.reads

    def setup(self, **kwargs: Any) -> None:
        """py_trees hands every behaviour the controller's tick context at tree setup;
        the layer's frame learns its ``reads`` here, once its ``__init__`` has run."""
        self.context = kwargs.get("context")
        self.frame = Frame.for_layer(self.name, self.layer.reads, _NO_SNAPSHOT)

    def update(self) -> Status:
        context = self.context
        current_frame(context, self.name)
        assert context is not None
        layer, frame = self.layer, self.frame
        try:
            applies = layer.applies(frame)
            if applies is not True and applies is not False:
                applies = _checked_applies(applies, context, self.name)
            if not applies:
                return Status.FAILURE
            command = layer.command(frame)
        except Exception as exc:
            error = context.blame(self.name, exc)  # so the error report can name the layer
            if error is None:
                raise
            raise error from exc
        context.propose(self.name, command)
        return Status.RUNNING


_BOOL = "it must return True or False (a bool)"


def _checked_applies(value: object, context: TickContext, layer: str) -> bool:
    """``value`` as the bool ``applies`` meant (numpy's bool counts), else the
    :class:`LayerError` saying what it returned: ``None`` would silently read as "never
    applies" (a missing ``return``), any other object by its truth ("no" as "always")."""
    if isinstance(value, np.bool_):
        return bool(value)
    context.failed_layer = layer
    if value is None:
        raise LayerError(f"applies() returned None (is a 'return' missing?); {_BOOL}", layer)
    raise LayerError(
        f"applies() returned {reprlib.repr(value)}, a {type(value).__name__}; {_BOOL}", layer
    )


def layer_node(layer: Layer) -> LayerNode:
    """The node that runs ``layer``, refusing a layer whose ``__init__`` skipped
    ``super().__init__()`` (it has none, and would fail later with a message naming
    neither the layer nor the fix)."""
    node = vars(layer).get("_Layer__node")
    if not isinstance(node, LayerNode):
        cls = type(layer).__name__
        raise LayerError(
            f"{cls}.__init__ never calls super().__init__(); add super().__init__() as the "
            f"first line of {cls}.__init__",
            cls,
        )
    return node


def as_behaviour(part: object) -> py_trees.behaviour.Behaviour:
    """The py_trees behaviour that runs ``part`` in a tree: a :class:`Layer`'s own node,
    or ``part`` itself when it already is a behaviour (a decorator, a composite).

    Controllers and :class:`~puckboard.behaviours.HoldFor` call it on what they are
    given; a py_trees composite of your own takes ``as_behaviour(layer)`` as a child.
    """
    if isinstance(part, py_trees.behaviour.Behaviour):
        return part
    if isinstance(part, Layer):
        return layer_node(part)
    if isinstance(part, type) and issubclass(part, (Layer, py_trees.behaviour.Behaviour)):
        name = part.__name__  # Controller([LineFollow, Cruise]): the objects were meant
        raise LayerError(f"got the class {name}; did you mean {name}()?")
    raise TypeError(
        f"expected a Layer (or a py_trees behaviour built from layers), got "
        f"{type(part).__name__} {part!r:.60}"
    )


def layer_of(node: py_trees.behaviour.Behaviour) -> Layer | None:
    """The layer ``node`` runs, ``None`` for any other behaviour of the tree."""
    return node.layer if isinstance(node, LayerNode) else None
