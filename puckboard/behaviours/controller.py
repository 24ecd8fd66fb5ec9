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

from collections.abc import Iterable, Iterator, Sequence

import py_trees
from py_trees.common import Status

from ..blackboard import Namespace
from ..records import WheelCommand
from .layer import Frame, Layer

__all__ = ["NO_LAYER", "Controller", "PrioritySelector"]

NO_LAYER = "(none)"
"""``command/layer`` when no layer applied (the robot then stops)."""


class PrioritySelector(py_trees.composites.Selector):
    """py_trees' ``Selector`` without memory, ticked without its costs that decide nothing.

    The arbiter runs every control cycle for every robot, and ``Selector.tick`` formats
    a debug message and looks up the ``Status`` members afresh at every step, on top of
    the priority decision itself. This tick takes the same steps in the same order for a
    selector without memory (initialise when not running, tick the children from the
    highest priority down, on the first that runs or succeeds stop every lower child that
    is not already invalid, take its status; fail when none does) and hands over to
    py_trees' own tick whenever its debug logging is on, or the selector has memory or
    no children.
    """

    def tick(self) -> Iterator[py_trees.behaviour.Behaviour]:
        children = self.children
        if self.memory or not children or py_trees.logging.level < py_trees.logging.Level.INFO:
            yield from super().tick()
            return
        if self.status != Status.RUNNING:
            self.current_child = children[0]
            self.initialise()
        previous = self.current_child
        for child in children:
            for node in child.tick():
                yield node
                if node is child:
                    status = node.status
                    if status == Status.RUNNING or status == Status.SUCCESS:
                        self.current_child = child
                        if previous is not child:
                            # a higher priority took over: invalidate everything below it
                            for lower in children[children.index(child) + 1 :]:
                                if lower.status != Status.INVALID:
                                    lower.stop(Status.INVALID)
                        if status == Status.SUCCESS:
                            self.stop(status)
                        else:
                            self.status = status
                        yield self
                        return
        self.stop(Status.FAILURE)
        self.current_child = children[-1]
        yield self


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
        self.root = PrioritySelector(name, memory=False, children=list(layers))
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
            self._tick_tree()
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

    def _tick_tree(self) -> None:
        """``self.tree.tick()``, without its per-node visitor bookkeeping when nobody uses it.

        ``BehaviourTree.tick`` builds a list of visitors for every node it ticks and walks
        the whole tree again afterwards, even with no visitors or handlers: at control
        rates that walk costs as much as the layers' own decisions. With none attached
        the root's own tick does exactly the same work; attach a visitor or a handler to
        :attr:`tree` and the full ``tick`` runs again.
        """
        tree = self.tree
        if tree.visitors or tree.pre_tick_handlers or tree.post_tick_handlers:
            tree.tick()
            return
        for _node in self.root.tick():
            pass
        tree.count += 1

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
