"""The arbiter's shape in plain py_trees: what a tick costs with nothing of puckboard's.

Four behaviours under a ``Selector`` without memory, each reading one sensor value
through a py_trees blackboard ``Client`` and writing a wheel command when it applies,
ticked through ``BehaviourTree.tick()`` as a py_trees user would. The second behaviour
applies, as line following does on most steps of the pass. The ``core`` suite sets
puckboard's arbiter beside it; the ``floor`` suite counts two of these ticks (one per
robot) in the two-robot pass's floor.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

__all__ = ["bare_selector"]


def bare_selector() -> Callable[[], None]:
    """A set-up py_trees tree of four reading behaviours; returns its ``tick``.

    It uses py_trees' process-wide blackboard: call
    ``py_trees.blackboard.Blackboard.clear()`` when done timing.
    """
    import py_trees

    py_trees.blackboard.Blackboard.clear()
    writer = py_trees.blackboard.Client(name="sensors")
    writer.register_key("ground", access=py_trees.common.Access.WRITE)
    writer.register_key("proximity", access=py_trees.common.Access.WRITE)
    writer.set("ground", (0.9, 0.1, 0.9))
    writer.set("proximity", tuple([0.05] * 8))

    class _Layer(py_trees.behaviour.Behaviour):
        def __init__(self, name: str, key: str, wants: Callable[[Any], bool]) -> None:
            super().__init__(name)
            self.key = key
            self.wants = wants
            self.bb = self.attach_blackboard_client(name=name)
            self.bb.register_key(key, access=py_trees.common.Access.READ)
            self.bb.register_key("cmd", access=py_trees.common.Access.WRITE)

        def update(self) -> py_trees.common.Status:
            reading = self.bb.get(self.key)
            if not self.wants(reading):
                return py_trees.common.Status.FAILURE
            self.bb.set("cmd", (1.0, 1.0))
            return py_trees.common.Status.RUNNING

    children = [
        _Layer("avoid", "proximity", lambda p: min(p[0], p[7]) < 0.05),
        _Layer("line", "ground", lambda g: min(g) < 0.5),
        _Layer("wall", "proximity", lambda p: p[2] < 0.05),
        _Layer("cruise", "ground", lambda g: True),
    ]
    root = py_trees.composites.Selector("arbiter", memory=False, children=children)
    tree = py_trees.trees.BehaviourTree(root)
    tree.setup()
    return tree.tick
