"""Seconds each layer's own code takes, measured by a py_trees visitor while asked.

A controller slower than its control period should say which layer is slow
(:mod:`puckboard.control.tick_timing`). py_trees hands every behaviour it ticks to the
tree's visitors as the tick goes, so a visitor that reads a clock at the start of the
tick and at each visit knows how long each ticked node took since the one before: for a
layer's node that is the layer's ``applies`` and ``command`` (and py_trees' own steps
around them). The controller adds what each layer's ``observe`` took, which it calls
before the tree is ticked.

The visitor is attached only while timing is asked for
(:meth:`~puckboard.behaviours.Controller.time_layers`): a tree with no visitor is
ticked by py_trees' ``tick_once``, which pays nothing for timing, and nothing is ever
set on a layer or its node.
"""

from __future__ import annotations

from collections.abc import Callable

import py_trees

from .layer import LayerNode

__all__ = ["LayerTiming"]


class LayerTiming(py_trees.visitors.VisitorBase):
    """Adds the seconds each layer takes to ``timings[layer name]``, read from ``clock``."""

    def __init__(self, timings: dict[str, float], clock: Callable[[], float]) -> None:
        super().__init__(full=False)  # only the nodes ticked this tick
        self.timings = timings
        self.clock = clock
        self._last = 0.0

    def add(self, layer: str, seconds: float) -> None:
        """Add ``seconds`` to ``layer``'s total (the controller's ``observe`` pass)."""
        self.timings[layer] = self.timings.get(layer, 0.0) + seconds

    # -- the visitor protocol: py_trees calls these from BehaviourTree.tick() ------------------
    def initialise(self) -> None:
        self._last = self.clock()

    def run(self, behaviour: py_trees.behaviour.Behaviour) -> None:
        now = self.clock()
        if isinstance(behaviour, LayerNode):
            self.add(behaviour.name, now - self._last)
        self._last = now
