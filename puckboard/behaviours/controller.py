"""A controller: layers under a priority arbiter, ticked against one robot's blackboard.

The arbiter is a py_trees ``Selector`` *without memory*: each tick it asks the layers
from the highest priority down and gives the wheels to the first that applies. When a
higher layer takes over, py_trees stops the layer that had control (``terminate`` with
``INVALID``), which is exactly subsumption's suppression of the lower layer.

The Selector stops asking at the first layer that applies, so a tick alone would leave
the layers below the driver unaware of the world. In Brooks' subsumption every layer
runs all the time and suppression acts only on outputs; so before the arbiter asks
anyone, the controller lets every :class:`~puckboard.behaviours.Layer` of the tree
(inside decorators and composites too) ``observe`` the tick's frame. A controller with
``requires=`` asks nobody, ``observe`` included, while a required key is missing or
stale: the robot stops, and no layer has to handle a required reading that has not
arrived.

Each tick writes two keys to the robot's namespace: ``command/wheels`` (the
:class:`~puckboard.records.WheelCommand`) and ``command/layer`` (the name of the layer in
control), so traces, plots and monitors can show who drove when.

The first tick against a namespace checks that every key the layers read is one the
robot can have: a sensor key, or a key declared or written on its namespace (knowledge
sources declare theirs when they are attached). A misspelt key would otherwise read as
"no value" for ever, and the layer would silently never apply.

What can be checked without a robot is checked once, when the controller is built: every
layer has a ``command`` of its own, no layer object is in two places, and no two layers
share a name (``--set layer.NAME.attr``, traces and colours tell layers apart by name).
Each mistake is one :class:`~puckboard.errors.LayerError` line naming the layer and the
fix, rather than a failure at the first tick the layer is asked (or never).
"""

from __future__ import annotations

import difflib
import time
from collections.abc import Callable, Iterable, Sequence

import py_trees
from py_trees.common import Status

from ..blackboard import Namespace, Snapshot
from ..errors import LayerError
from ..records import WheelCommand
from .context import ROBOT_KEYS, TickContext
from .layer import Layer, LayerNode, as_behaviour, layer_of
from .layer_timing import LayerTiming

__all__ = ["NO_LAYER", "Controller"]

NO_LAYER = "(none)"
"""``command/layer`` when no layer applied (the robot then stops)."""


class Controller:
    """Arbitrates ``layers`` (highest priority first) into one wheel command per tick.

    ``layers`` may contain :class:`Layer` objects or any py_trees behaviour built from
    them (a :class:`~puckboard.behaviours.HoldFor` decorator, a Sequence of
    :func:`~puckboard.behaviours.as_behaviour` nodes, ...).

    ``requires`` names keys that must be fresh: when one is missing or stale the robot is
    commanded to stop instead of acting on old data.

    Each tick, every :class:`Layer` of the tree first observes the frame
    (:meth:`Layer.observe`), then the arbiter asks the layers in priority order; with
    ``requires``, only once every required key is fresh.
    """

    #: The controller's name: the arbiter's, and ``controller`` in results.
    name: str

    def __init__(
        self,
        layers: Sequence[Layer | py_trees.behaviour.Behaviour],
        *,
        name: str = "Arbiter",
        requires: Iterable[str] = (),
    ) -> None:
        if isinstance(layers, Controller):
            raise LayerError(
                f"got the controller {layers.name!r} where its layers belong; use it as it "
                "is, or build a new one from layers: Controller([layer, ...])"
            )
        if not layers:
            raise LayerError("a Controller needs at least one layer: Controller([Cruise()])")
        if isinstance(requires, str):
            raise TypeError(
                f"requires={requires!r} is one string; write a tuple: requires=({requires!r},)"
            )
        if isinstance(layers, (Layer, type)):
            raise TypeError(f"a Controller takes a list of layers: Controller([{layers!r:.40}])")
        children = [as_behaviour(layer) for layer in layers]
        _check_placed_once(children)
        self.name = name
        self.root = py_trees.composites.Selector(name, memory=False, children=children)
        self.tree = py_trees.trees.BehaviourTree(self.root)
        self.requires = tuple(requires)
        reads: set[str] = set(self.requires)
        for node in self.root.iterate():
            reads.update(keys_read(node))
        self.reads = tuple(sorted(reads))
        nodes = [node for node in self.root.iterate() if isinstance(node, LayerNode)]
        #: Every layer of the tree, in tree order: each observes every tick's frame.
        self.every_layer = [node.layer for node in nodes]
        _check_layers(self.every_layer)
        #: What the behaviours of the tree are handed for each tick (see TickContext).
        self.context = TickContext()
        self.active_layer: str = NO_LAYER
        self.last_command = WheelCommand.stop()
        #: Ticks in which a layer was asked, and in which one of them applied: a
        #: controller none of whose layers ever applies leaves the robot standing, and
        #: the episode says so (its layers' ``applies`` are worth a look).
        self.asked_ticks = 0
        self.driven_ticks = 0
        self._checked: Namespace | None = None  # the namespace whose keys were checked
        self._command_keys = ("command/wheels", "command/layer")  # as absolute keys there
        self._timing: LayerTiming | None = None  # attached while the layers are timed
        self.tree.setup(context=self.context)
        #: Each layer with the frame it reads through (made at setup, see LayerNode).
        #: A layer that keeps Layer's own ``observe``, which does nothing, is not called
        #: (unless its layers are timed, where every layer's observe is timed).
        self._frames = [(node.layer, node.frame, _observes(node.layer)) for node in nodes]

    @property
    def failed_layer(self) -> str | None:
        """The layer whose ``observe``, ``applies`` or ``command`` raised during the last
        tick, if any (the loop's error report names it)."""
        return self.context.failed_layer

    @property
    def layers(self) -> list[Layer | py_trees.behaviour.Behaviour]:
        """The top-level layers (or the behaviours built from them), highest priority
        first."""
        return [layer_of(child) or child for child in self.root.children]

    def find(self, name: str) -> Layer:
        """The layer called ``name`` (to tune a parameter, for instance)."""
        for layer in self.every_layer:
            if layer.name == name:
                return layer
        names = [layer.name for layer in self.every_layer]
        raise KeyError(f"no layer named {name!r}; layers: {', '.join(names)}")

    def tick(self, ns: Namespace) -> WheelCommand:
        """Snapshot ``ns``, let every layer observe, tick the tree, write and return the
        winning wheel command."""
        if ns is not self._checked:
            self.check_keys(ns)
        snapshot = ns.snapshot(self.reads)
        context = self.context
        context.begin(snapshot)
        status = snapshot.status
        for key in self.requires:
            if status(key) != "fresh":  # no layer acts, or learns, on missing or old data
                self.root.stop(Status.INVALID)
                layer_name, cmd = "(stale inputs)", WheelCommand.stop()
                break
        else:
            self._observe(snapshot, self._timing)  # every layer, whoever drives
            tree = self.tree
            if tree.visitors or tree.pre_tick_handlers or tree.post_tick_handlers:
                tree.tick()  # a trace, a timing or a user's visitor sees every node
            else:
                # nothing watches: py_trees' own tick of the root, the same ticks without
                # the tree's walks for visitors (still counted, as BehaviourTree.tick does)
                self.root.tick_once()
                tree.count += 1
            self.asked_ticks += 1
            proposal = context.proposal
            if proposal is None:
                layer_name, cmd = NO_LAYER, WheelCommand.stop()
            else:
                layer_name, cmd = proposal
                self.driven_ticks += 1
        self.active_layer = layer_name
        self.last_command = cmd
        wheels, layer = self._command_keys
        ns.board.write_many({wheels: cmd, layer: layer_name}, stamp=snapshot.now, writer=self.name)
        return cmd

    def _observe(self, snapshot: Snapshot, timing: LayerTiming | None) -> None:
        """Every layer observes the snapshot (subsumption: arbitration suppresses outputs,
        not perception); with ``timing``, each adds the seconds its ``observe`` took."""
        context = self.context
        for layer, frame, observes in self._frames:
            frame.point_at(snapshot)
            if not observes and timing is None:
                continue
            start = timing.clock() if timing is not None else 0.0
            try:
                layer.observe(frame)
            except Exception as exc:
                error = context.blame(layer.name, exc)
                if error is None:
                    raise
                raise error from exc
            finally:
                if timing is not None:
                    timing.add(layer.name, timing.clock() - start)

    def time_layers(
        self, timings: dict[str, float] | None, clock: Callable[[], float] = time.perf_counter
    ) -> None:
        """From the next tick on, add the seconds each layer's own code takes
        (``observe``, ``applies``, ``command``) to ``timings[layer name]``, read from
        ``clock``; ``None`` stops timing. The controller times ``observe`` where it
        calls it; ``applies`` and ``command`` are timed by a py_trees visitor
        (:class:`~puckboard.behaviours.layer_timing.LayerTiming`) attached to the tree
        only while timing, so an untimed tick pays nothing for it and nothing is set on
        a layer or its node."""
        if self._timing is not None:
            self.tree.visitors.remove(self._timing)
            self._timing = None
        if timings is not None:
            self._timing = LayerTiming(timings, clock)
            self.tree.add_visitor(self._timing)

    def check_keys(self, ns: Namespace) -> None:
        """Refuse a key read by a layer (or in ``requires``) that robot ``ns`` cannot have.

        Done at the first tick against a namespace rather than when the controller is
        built: the keys a knowledge source derives exist only once it is attached.
        """
        known = ROBOT_KEYS.union(ns.declared_keys())
        for node in self.root.iterate():
            for key in keys_read(node):
                if key not in known:
                    self.context.failed_layer = node.name
                    raise LayerError(f"reads {_unknown_key(key, ns, known)}", node.name)
        for key in self.requires:
            if key not in known:
                unknown = _unknown_key(key, ns, known)
                raise LayerError(f"controller {self.name!r} requires {unknown}")
        self._checked = ns
        self._command_keys = (ns.key("command/wheels"), ns.key("command/layer"))

    def reset(self) -> None:
        """Start afresh: stop every behaviour of the tree, let every layer forget what it
        holds (:meth:`Layer.reset`) and clear the last decision."""
        self.root.stop(Status.INVALID)
        for layer in self.every_layer:
            layer.reset()
        self.asked_ticks = self.driven_ticks = 0
        self.active_layer = NO_LAYER
        self.last_command = WheelCommand.stop()

    def ascii_tree(self) -> str:
        """The tree as text, with the status of the last tick."""
        return py_trees.display.ascii_tree(self.root, show_status=True)

    def unicode_tree(self) -> str:
        return py_trees.display.unicode_tree(self.root, show_status=True)

    def __repr__(self) -> str:
        return f"<Controller {self.name!r}: {' > '.join(n.name for n in self.layers)}>"


def _observes(layer: Layer) -> bool:
    """Whether ``layer`` has an ``observe`` of its own (its class's, or one set on it):
    Layer's own does nothing, so calling it on every tick of every layer would only
    cost time."""
    return "observe" in vars(layer) or type(layer).observe is not Layer.observe


def _check_placed_once(children: list[py_trees.behaviour.Behaviour]) -> None:
    """Refuse a layer (or behaviour) given twice, or one already in another tree: a
    layer object is one place in one controller (py_trees would say "already has
    parent", which names neither the layer's class nor the fix)."""
    seen: set[int] = set()
    for child in children:
        layer = layer_of(child)
        what = type(layer).__name__ if layer is not None else type(child).__name__
        if id(child) in seen:
            where = "twice in this controller"
        elif child.parent is not None:
            where = f"already in {child.parent.name!r}"
        else:
            seen.add(id(child))
            continue
        raise LayerError(
            f"the same {what} object is {where}; each place needs an object of its own: "
            f"build another ({what}(...)) for this one",
            child.name,
        )


def _check_layers(layers: list[Layer]) -> None:
    """Refuse, when the controller is built, a layer that could only fail once it runs:
    one with no ``command`` of its own, and two layers of one name (``--set
    layer.NAME.attr``, traces and colours tell layers apart by name)."""
    names: dict[str, Layer] = {}
    for layer in layers:
        cls = type(layer).__name__
        if type(layer).command is Layer.command:
            raise LayerError(
                f"{cls} has no command(frame); write one that returns WheelCommand(left, "
                "right), the wheel speeds in rad/s",
                layer.name,
            )
        if layer.name in names:
            raise LayerError(
                f"two layers are called {layer.name!r} ({type(names[layer.name]).__name__} "
                f"and {cls}); give one a name of its own: {cls}(..., name="
                f"{layer.name + '2'!r})",
                layer.name,
            )
        names[layer.name] = layer


def keys_read(node: py_trees.behaviour.Behaviour) -> tuple[str, ...]:
    """The ``reads`` of a behaviour of the tree, refusing what is not a tuple of keys."""
    reads = getattr(node, "reads", ())
    if isinstance(reads, str):  # tuple("proximity") would be its letters
        raise LayerError(
            f"reads = {reads!r} is one string; write a tuple: reads = ({reads!r},) "
            "(mind the comma)",
            node.name,
        )
    for key in reads:
        if not isinstance(key, str) or not key:
            raise LayerError(f"reads must name blackboard keys as text, got {key!r}", node.name)
    return tuple(reads)


def _unknown_key(key: str, ns: Namespace, known: Iterable[str]) -> str:
    close = difflib.get_close_matches(key, list(known), n=1)
    guess = f" (did you mean {close[0]!r}?)" if close else ""
    return (
        f"{key!r}, which robot {ns.name!r} does not have{guess}; its keys: "
        f"{', '.join(sorted(known))}. To read a key of your own, declare it on the robot's "
        f"namespace before the run (ns.declare({key!r})) or have a knowledge source "
        "write it"
    )
