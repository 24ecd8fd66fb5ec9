"""What the arbiter decided, seen from outside: every node's status after each tick.

A :class:`~puckboard.behaviours.controller.Controller` ticks a py_trees tree, and py_trees
hands every behaviour it ticks to the tree's *visitors*. A :class:`TreeTrace` is such a
visitor: it keeps, per node of the tree, whether the node was ticked this tick and the
status it returned. For the layers under the arbiter (a Selector without memory) that is
exactly subsumption's story: the layers above the winner were *asked* and did not apply
(``FAILURE``), the winner applies (``RUNNING``), the layers below were not asked at all.
A decorator such as :class:`~puckboard.behaviours.suppression.HoldFor` shows as
``RUNNING`` while it holds the wheels for a layer that no longer applies.

Recorders and live views attach one with :func:`trace`; the controller knows nothing of
it, and a trace only reads, so a run is the same with or without one.

Statuses are small integers (:data:`STATUS_NAMES` names them), kept in one preallocated
``int8`` array, so tracing costs one store per ticked node and no objects per tick.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt
import py_trees
from py_trees.common import Status

from .layer import LayerNode

if TYPE_CHECKING:
    from .controller import Controller

__all__ = ["NOT_TICKED", "STATUS_NAMES", "TreeTrace", "trace", "tree_nodes"]

#: Status codes: index into this tuple. 0: the node was not ticked ("not asked").
STATUS_NAMES: tuple[str, ...] = ("not ticked", "FAILURE", "RUNNING", "SUCCESS", "INVALID")
NOT_TICKED = 0
_CODE = {Status.FAILURE: 1, Status.RUNNING: 2, Status.SUCCESS: 3, Status.INVALID: 4}


def _kind(node: py_trees.behaviour.Behaviour) -> str:
    if isinstance(node, py_trees.composites.Selector):
        return "selector"
    if isinstance(node, py_trees.composites.Sequence):
        return "sequence"
    if isinstance(node, py_trees.composites.Parallel):
        return "parallel"
    if isinstance(node, py_trees.decorators.Decorator):
        return "decorator"
    if isinstance(node, LayerNode):
        return "layer"
    return "behaviour"


def _preorder(root: py_trees.behaviour.Behaviour) -> list[py_trees.behaviour.Behaviour]:
    """``root`` and everything under it, each parent before its children, children in
    priority order (py_trees' own ``iterate`` yields children first)."""
    out = [root]
    for child in root.children:
        out.extend(_preorder(child))
    return out


def tree_nodes(root: py_trees.behaviour.Behaviour) -> list[dict[str, Any]]:
    """The tree under ``root`` as plain data, parents before children in priority order.

    Each node: ``name``, ``type`` (its class; a layer's node gives its layer's),
    ``kind`` (``selector``, ``sequence``, ``parallel``, ``decorator``, ``layer`` or
    ``behaviour``), ``parent`` (index, -1 for the root) and ``depth``; composites also
    say whether they have ``memory``.
    """
    nodes = _preorder(root)
    index = {id(node): k for k, node in enumerate(nodes)}
    out: list[dict[str, Any]] = []
    for node in nodes:
        parent = -1 if node is root or node.parent is None else index[id(node.parent)]
        entry: dict[str, Any] = {
            "name": node.name,
            "type": type(node.layer if isinstance(node, LayerNode) else node).__name__,
            "kind": _kind(node),
            "parent": parent, "depth": 0 if parent < 0 else out[parent]["depth"] + 1,
        }  # fmt: skip
        if isinstance(node, py_trees.composites.Composite) and hasattr(node, "memory"):
            entry["memory"] = bool(node.memory)
        out.append(entry)
    return out


class TreeTrace(py_trees.visitors.VisitorBase):
    """The status of every node of one tree after its latest tick.

    ``status[k]`` is node ``k``'s code (see :data:`STATUS_NAMES`), nodes in the order of
    :attr:`nodes`. ``ticks`` counts the ticks seen: a controller that refuses to decide on
    stale inputs does not tick its tree, and a reader that compares ``ticks`` with its
    last look knows that nothing was asked. ``listeners`` are called with the trace after
    every tick.
    """

    def __init__(self, root: py_trees.behaviour.Behaviour) -> None:
        super().__init__(full=False)
        self.root = root
        self.nodes = tree_nodes(root)
        self._index = {id(node): k for k, node in enumerate(_preorder(root))}
        self.status: npt.NDArray[np.int8] = np.zeros(len(self.nodes), dtype=np.int8)
        self.ticks = 0
        self.listeners: list[Callable[[TreeTrace], None]] = []

    # -- the visitor protocol: py_trees calls these from BehaviourTree.tick() ------------------
    def initialise(self) -> None:
        self.status.fill(NOT_TICKED)

    def run(self, behaviour: py_trees.behaviour.Behaviour) -> None:
        k = self._index.get(id(behaviour))
        if k is not None:
            self.status[k] = _CODE.get(behaviour.status, 4)

    def finalise(self) -> None:
        self.ticks += 1
        for listener in self.listeners:
            listener(self)

    def codes(self) -> str:
        """The statuses as one digit per node (``"21000"``), for messages."""
        return "".join(str(int(c)) for c in self.status)


def trace(controller: Controller) -> TreeTrace:
    """The :class:`TreeTrace` of ``controller``'s tree, attached on first use.

    A recorder and a live view of the same run share one trace, so the tree is visited
    once per tick however many tools watch it.
    """
    tree = controller.tree
    for visitor in tree.visitors:
        if isinstance(visitor, TreeTrace) and visitor.root is controller.root:
            return visitor
    found = TreeTrace(controller.root)
    tree.add_visitor(found)
    return found
