"""The ``core`` suite: the blackboard and the arbiter, each next to its py_trees equivalent.

puckboard's blackboard and its subsumption arbiter replace py_trees' blackboard clients
and a ``Selector`` of four behaviours; a reader deciding whether that is worth it needs
both sides measured the same way on the same machine: a put+get, and one tick of four
layers reading sensors and writing a wheel command. Absolute times move with the
machine and its load; ``arbiter_over_selector``, the arbiter's tick divided by py_trees'
own Selector's from the same run, is the figure to quote.

Two parts of the arbiter's tick are measured on their own: ``observe_pass_us``, every
layer's ``observe`` (each layer's frame pointed at the snapshot, then the call), and
``tracing_adds_us``, what a :class:`~puckboard.behaviours.tracing.TreeTrace` (a
recording's or a live view's) adds to a tick.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from .bare_tree import bare_selector
from .timing import REPEATS, seconds_per_call

__all__ = ["run_suite"]


def _median_us(fn: Callable[[], Any], calls: int) -> float:
    return seconds_per_call(fn, calls) * 1e6


def run_suite(steps: int | None = None) -> dict[str, Any]:
    """Blackboard put+get and a 4-layer arbiter tick, each next to its py_trees equivalent."""
    import numpy as np
    import py_trees

    from ..backends.base import declare_robot_keys
    from ..behaviours import load_controller
    from ..behaviours.layer import layer_node
    from ..behaviours.tracing import trace
    from ..blackboard import Blackboard
    from ..records import Ground, Pose, Proximity, Sensor

    calls = steps or 5000
    out: dict[str, Any] = {"calls_per_repeat": calls, "repeats": REPEATS}

    board = Blackboard()
    value = 1.0

    def bb_put_get() -> None:
        board.put("robot/x", value)
        board.get("robot/x")

    out["blackboard_put_get_us"] = _median_us(bb_put_get, calls)

    py_trees.blackboard.Blackboard.clear()
    client = py_trees.blackboard.Client(name="bench")
    client.register_key("x", access=py_trees.common.Access.WRITE)

    def pt_set_get() -> None:
        client.set("x", value)
        client.get("x")

    out["py_trees_client_set_get_us"] = _median_us(pt_set_get, calls)

    # the improved controller (4 layers) ticking on a namespace of fresh records
    board2 = Blackboard(clock=lambda: 0.0)
    ns = board2.namespace("epuck")
    declare_robot_keys(ns)
    prox = Proximity(np.array([0.05, 0.05, 0.05, 0.05, 0.05, 0.05, 0.05, 0.05]), np.zeros(8))
    ns.put_many(
        {
            Sensor.PROXIMITY.key: prox,
            Sensor.GROUND.key: Ground(np.array([0.9, 0.1, 0.9]), np.array([920.0, 100, 920])),
            Sensor.POSE.key: Pose(0.0, 0.0, 0.0),
        },
        stamp=0.0,
    )
    controller = load_controller("improved")
    out["arbiter_tick_us"] = _median_us(lambda: controller.tick(ns), calls)
    out["arbiter_layers"] = len(controller.layers)
    out["arbiter_active_layer"] = controller.active_layer
    traced = load_controller("improved")
    trace(traced)
    out["arbiter_tick_traced_us"] = _median_us(lambda: traced.tick(ns), calls)
    out["tracing_adds_us"] = out["arbiter_tick_traced_us"] - out["arbiter_tick_us"]
    snapshot = ns.snapshot(controller.reads)
    frames = [(layer, layer_node(layer).frame) for layer in controller.every_layer]

    def observe_pass() -> None:  # the controller's own loop, on the same snapshot
        for layer, frame in frames:
            frame.point_at(snapshot)
            layer.observe(frame)

    out["observe_pass_us"] = _median_us(observe_pass, calls)

    # the same shape in plain py_trees: 4 children reading via a Client, writing a command
    tick = bare_selector()
    out["py_trees_selector_tick_us"] = _median_us(tick, calls)
    out["arbiter_over_selector"] = round(
        out["arbiter_tick_us"] / out["py_trees_selector_tick_us"], 2
    )
    py_trees.blackboard.Blackboard.clear()
    return out
