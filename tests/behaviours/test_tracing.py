"""A TreeTrace sees what the arbiter decided: who was asked, who applied, who held."""

from __future__ import annotations

import numpy as np

from puckboard.behaviours import Controller, Cruise, HoldFor, Layer, improved
from puckboard.behaviours.tracing import STATUS_NAMES, trace, tree_nodes
from puckboard.blackboard import Blackboard
from puckboard.records import PROX_NAMES, Ground, Proximity, WheelCommand


class Clock:
    t = 0.0

    def __call__(self) -> float:
        return self.t


class Flag(Layer):
    """Applies while the blackboard key ``flag/<name>`` is true."""

    def __init__(self, name: str) -> None:
        super().__init__(name)
        self.reads = (f"flag/{name}",)

    def applies(self, frame):
        return bool(frame.value(f"flag/{self.name}", False))

    def command(self, frame):
        return WheelCommand(1.0, 1.0)


def statuses(controller) -> dict[str, str]:
    tr = trace(controller)
    return {n["name"]: STATUS_NAMES[int(c)] for n, c in zip(tr.nodes, tr.status)}


def test_nodes_are_listed_parents_first_in_priority_order_with_decorators():
    ctl = Controller([HoldFor(Flag("back_off"), 0.5), Flag("follow"), Cruise(0.1)], name="arb")
    nodes = tree_nodes(ctl.root)
    assert [(n["name"], n["kind"], n["parent"], n["depth"]) for n in nodes] == [
        ("arb", "selector", -1, 0),
        ("HoldFor(back_off, 0.5s)", "decorator", 0, 1),
        ("back_off", "layer", 1, 2),
        ("follow", "layer", 0, 1),
        ("Cruise", "layer", 0, 1),
    ]
    assert nodes[0]["memory"] is False and nodes[1]["type"] == "HoldFor"


def test_layers_above_the_winner_failed_the_winner_runs_those_below_were_not_asked():
    ctl = Controller([Flag("high"), Flag("mid"), Flag("low"), Cruise(0.1)], name="arb")
    trace(ctl)  # attached before the first tick
    ns = Blackboard(clock=Clock()).namespace("r")
    for name in ("high", "mid", "low"):
        ns.declare(f"flag/{name}")  # keys of the test's own: declared, as a controller checks
    ns.put("flag/mid", True)
    ctl.tick(ns)
    assert statuses(ctl) == {
        "arb": "RUNNING", "high": "FAILURE", "mid": "RUNNING", "low": "not ticked",
        "Cruise": "not ticked",
    }  # fmt: skip
    assert ctl.active_layer == "mid"
    ns.put("flag/mid", False)
    ctl.tick(ns)
    assert statuses(ctl) == {
        "arb": "RUNNING", "high": "FAILURE", "mid": "FAILURE", "low": "FAILURE",
        "Cruise": "RUNNING",
    }  # fmt: skip


def test_a_hold_shows_the_decorator_running_over_a_layer_that_no_longer_applies():
    clock = Clock()
    ctl = Controller([HoldFor(Flag("trig"), 0.5, clock=clock), Cruise(0.1)], name="arb")
    trace(ctl)
    ns = Blackboard(clock=clock).namespace("r")
    ns.put("flag/trig", True)
    ctl.tick(ns)
    ns.put("flag/trig", False)
    clock.t = 0.3
    ctl.tick(ns)
    assert ctl.active_layer == "trig"
    assert statuses(ctl) == {
        "arb": "RUNNING", "HoldFor(trig, 0.5s)": "RUNNING", "trig": "FAILURE",
        "Cruise": "not ticked",
    }  # fmt: skip


def test_stale_inputs_leave_the_tree_unticked_and_the_count_says_so():
    clock = Clock()
    ns = Blackboard(clock=clock).namespace("r")
    ns.declare("proximity", max_age=0.1)
    ctl = improved()
    tr = trace(ctl)
    ns.put("proximity", Proximity(np.full(8, 0.05), np.zeros(8)))
    ns.put("ground", Ground(np.ones(3), np.full(3, 1023.0)))
    ctl.tick(ns)
    assert tr.ticks == 1 and statuses(ctl)["Cruise"] == "RUNNING"
    clock.t = 1.0
    ctl.tick(ns)
    assert ctl.active_layer == "(stale inputs)"
    assert tr.ticks == 1  # nobody was asked this time


def test_one_trace_per_tree_however_many_tools_ask_and_it_changes_no_decision():
    def run(watched: bool) -> list[tuple[str, WheelCommand]]:
        ctl = improved()
        if watched:
            assert trace(ctl) is trace(ctl)
            assert len(ctl.tree.visitors) == 1
        ns = Blackboard(clock=Clock()).namespace("r")
        out = []
        for k in range(8):
            distance = np.full(8, 0.05)
            distance[PROX_NAMES.index("front_left")] = 0.05 - 0.005 * k
            ns.put("proximity", Proximity(distance, np.zeros(8)))
            ns.put("ground", Ground(np.full(3, 1.0 - 0.1 * k), np.full(3, 1023.0)))
            out.append((ctl.tick(ns), ctl.active_layer))
        return out

    assert run(watched=True) == run(watched=False)
