"""A controller: layers under a priority arbiter, ticked against one robot's blackboard.

The arbiter is a py_trees ``Selector`` *without memory*: each tick it asks the layers
from the highest priority down and gives the wheels to the first that applies. When a
higher layer takes over, py_trees stops the layer that had control (``terminate`` with
``INVALID``), which is exactly subsumption's suppression of the lower layer.

Each tick writes two keys to the robot's namespace: ``command/wheels`` (the
:class:`~puckboard.records.WheelCommand`) and ``command/layer`` (the name of the layer in
control), so traces, plots and monitors can show who drove when.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import py_trees
from py_trees.common import Status

from ..blackboard import Namespace
from ..records import WheelCommand
from .layer import Frame, Layer

__all__ = ["NO_LAYER", "Controller"]

NO_LAYER = "(none)"
"""``command/layer`` when no layer applied (the robot then stops)."""


class Controller:
    """Arbitrates ``layers`` (highest priority first) into one wheel command per tick.

    ``layers`` may contain :class:`Layer` objects or any py_trees behaviour built from
    them (a :class:`~puckboard.behaviours.HoldFor` decorator, a Sequence, ...).

    ``requires`` names keys that must be fresh: when one is missing or stale the robot is
    commanded to stop instead of acting on old data.
    """

    def __init__(
        self,
        layers: Sequence[py_trees.behaviour.Behaviour],
        *,
        name: str = "Arbiter",
        requires: Iterable[str] = (),
    ) -> None:
        if not layers:
            raise ValueError("a Controller needs at least one layer")
        for layer in layers:
            if not isinstance(layer, py_trees.behaviour.Behaviour):
                raise TypeError(
                    f"controller layers must be Layer (py_trees behaviour) objects, got "
                    f"{type(layer).__name__}"
                )
        self.name = name
        self.root = py_trees.composites.Selector(name, memory=False, children=list(layers))
        self.tree = py_trees.trees.BehaviourTree(self.root)
        self.requires = tuple(requires)
        reads: set[str] = set(self.requires)
        for node in self.root.iterate():
            reads.update(getattr(node, "reads", ()))
        self.reads = tuple(sorted(reads))
        self.frame: Frame | None = None
        self.active_layer: str = NO_LAYER
        self.last_command = WheelCommand.stop()
        self._proposal: tuple[py_trees.behaviour.Behaviour, WheelCommand] | None = None
        #: the layer whose applies() or command() raised during the last tick, if any
        self.failed_layer: str | None = None
        self.tree.setup(controller=self)

    @property
    def layers(self) -> list[py_trees.behaviour.Behaviour]:
        """The top-level layers, highest priority first."""
        return list(self.root.children)

    def find(self, name: str) -> Layer:
        """The layer called ``name`` (to tune a parameter, for instance)."""
        for node in self.root.iterate():
            if node.name == name and isinstance(node, Layer):
                return node
        names = [n.name for n in self.root.iterate() if isinstance(n, Layer)]
        raise KeyError(f"no layer named {name!r}; layers: {', '.join(names)}")

    def propose(self, layer: py_trees.behaviour.Behaviour, command: WheelCommand) -> None:
        """Called by the layer in control during the tick."""
        if not isinstance(command, WheelCommand):
            raise TypeError(
                f"layer {layer.name!r} returned {command!r}; command() must return a WheelCommand"
            )
        self._proposal = (layer, command)

    def tick(self, ns: Namespace) -> WheelCommand:
        """Snapshot ``ns``, tick the tree, write and return the winning wheel command."""
        snapshot = ns.snapshot(self.reads)
        self.frame = Frame(snapshot)
        self._proposal = None
        self.failed_layer = None
        status = snapshot.status
        for key in self.requires:
            if status(key) != "fresh":
                self.root.stop(Status.INVALID)
                layer_name, cmd = "(stale inputs)", WheelCommand.stop()
                break
        else:
            self.tree.tick()
            if self._proposal is None:
                layer_name, cmd = NO_LAYER, WheelCommand.stop()
            else:
                layer_name, cmd = self._proposal[0].name, self._proposal[1]
        self.active_layer = layer_name
        self.last_command = cmd
        ns.put_many(
            {"command/wheels": cmd, "command/layer": layer_name},
            stamp=snapshot.now,
            writer=self.name,
        )
        return cmd

    def reset(self) -> None:
        """Stop every layer (they forget held state) and clear the last decision."""
        self.root.stop(Status.INVALID)
        self.active_layer = NO_LAYER
        self.last_command = WheelCommand.stop()

    def ascii_tree(self) -> str:
        """The tree as text, with the status of the last tick."""
        return py_trees.display.ascii_tree(self.root, show_status=True)

    def unicode_tree(self) -> str:
        return py_trees.display.unicode_tree(self.root, show_status=True)

    def __repr__(self) -> str:
        return f"<Controller {self.name!r}: {' > '.join(n.name for n in self.layers)}>"
