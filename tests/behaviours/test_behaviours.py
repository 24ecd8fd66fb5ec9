"""Layers, the priority arbiter, timed suppression and the ported controllers."""

from __future__ import annotations

import pytest
from layer_readings import MAX, Clock, ground, prox
from py_trees.common import Status

from puckboard.behaviours import (
    NO_LAYER,
    Controller,
    Cruise,
    FrontBraitenbergAvoid,
    FrontObstacleLeftTurn,
    HoldFor,
    Layer,
    LineFollow,
    SideWallKeep,
    as_behaviour,
    improved,
    load_controller,
    stock,
)
from puckboard.behaviours.tracing import trace
from puckboard.blackboard import Blackboard
from puckboard.records import WheelCommand

#: the keys the test layers below read: keys of their own, so declared (a controller
#: refuses a key its robot cannot have)
FLAG_KEYS = ("flag/high", "flag/low", "flag/only", "flag/trig")


def make_ns(clock=None):
    bb = Blackboard(clock=clock or Clock())
    ns = bb.namespace("r")
    for key in FLAG_KEYS:
        ns.declare(key)
    return ns


class Flag(Layer):
    """A test layer that applies when a blackboard flag is set."""

    reads = ("flag",)

    def __init__(self, name, speed):
        super().__init__(name)
        self.speed = speed

    def applies(self, frame):
        return bool(frame.value(f"flag/{self.name}", False))

    def command(self, frame):
        return WheelCommand(self.speed, self.speed)


def flags_controller():
    high, low = Flag("high", 1.0), Flag("low", 0.5)
    high.reads = ("flag/high",)
    low.reads = ("flag/low",)
    return Controller([high, low, Cruise(0.1)]), high, low


def test_arbiter_picks_highest_active_layer_and_stops_preempted_one():
    ctl, high, low = flags_controller()
    ns = make_ns()
    assert ctl.tick(ns) == WheelCommand(0.1, 0.1)
    assert ctl.active_layer == "Cruise"
    ns.put("flag/low", True)
    assert ctl.tick(ns) == WheelCommand(0.5, 0.5)
    assert ctl.active_layer == "low"
    ns.put("flag/high", True)
    assert ctl.tick(ns) == WheelCommand(1.0, 1.0)
    assert ctl.active_layer == "high"
    assert as_behaviour(low).status == Status.INVALID  # pre-empted layer was stopped
    # the decision is on the blackboard for traces and plots
    assert ns.value("command/layer") == "high"
    assert ns.value("command/wheels") == WheelCommand(1.0, 1.0)


def test_no_layer_applies_means_stop():
    high = Flag("only", 1.0)
    high.reads = ("flag/only",)
    ctl = Controller([high])
    ns = make_ns()
    assert ctl.tick(ns) == WheelCommand.stop()
    assert ctl.active_layer == NO_LAYER


def test_required_stale_inputs_stop_the_robot():
    clock = Clock()
    ns = make_ns(clock)
    ns.declare("proximity", max_age=0.1)
    ctl = improved()
    ns.put("proximity", prox())
    assert ctl.tick(ns) == WheelCommand(MAX, MAX)
    clock.t = 1.0
    assert ctl.tick(ns) == WheelCommand.stop()
    assert ctl.active_layer == "(stale inputs)"


def test_hold_for_keeps_control_after_trigger_with_injected_clock():
    clock = Clock()
    trig = Flag("trig", 2.0)
    trig.reads = ("flag/trig",)
    held = HoldFor(trig, 0.5, clock=clock)
    ctl = Controller([held, Cruise(0.1)])
    ns = make_ns(clock)
    ns.put("flag/trig", True)
    assert ctl.tick(ns) == WheelCommand(2.0, 2.0)
    ns.put("flag/trig", False)
    clock.t = 0.3
    assert ctl.tick(ns) == WheelCommand(2.0, 2.0)  # still held
    assert ctl.active_layer == "trig"
    clock.t = 0.6
    assert ctl.tick(ns) == WheelCommand(0.1, 0.1)  # hold expired
    with pytest.raises(ValueError, match=">= 0"):
        HoldFor(Flag("x", 1.0), -1)


def frame_for(ns, layer_reads=("proximity", "ground")):
    from puckboard.behaviours.layer import Frame

    return Frame(ns.snapshot(layer_reads))


@pytest.mark.parametrize(
    ("g", "expected"),
    [
        ((0.1, 1.0, 1.0), (0.25 * MAX, MAX)),  # line under left sensor: turn left
        ((1.0, 1.0, 0.1), (MAX, 0.25 * MAX)),
        ((0.1, 0.1, 0.1), (0.25 * MAX, 0.25 * MAX)),
    ],
)
def test_stock_line_follow_matches_code_4_13(g, expected):
    ns = make_ns()
    ns.put("ground", ground(*g))
    layer = LineFollow(MAX, inner_factor=0.25)
    f = frame_for(ns)
    assert layer.applies(f)
    cmd = layer.command(f)
    assert (cmd.left, cmd.right) == (pytest.approx(expected[0]), pytest.approx(expected[1]))


@pytest.mark.parametrize(
    ("g", "expected"),
    [
        ((1.0, 0.1, 0.1), (MAX, -0.75 * MAX)),  # centre+right dark: sharp right
        ((0.1, 0.1, 1.0), (-0.75 * MAX, MAX)),  # centre+left dark: sharp left
        ((0.1, 0.1, 0.1), (-MAX, MAX)),  # all dark: spin left
        ((0.1, 1.0, 1.0), (0.2 * MAX, MAX)),
        ((1.0, 1.0, 0.1), (MAX, 0.2 * MAX)),
    ],
)
def test_improved_line_follow_matches_code_4_14(g, expected):
    ns = make_ns()
    ns.put("ground", ground(*g))
    layer = LineFollow(MAX, inner_factor=0.2, recovery=True)
    cmd = layer.command(frame_for(ns))
    assert (cmd.left, cmd.right) == (pytest.approx(expected[0]), pytest.approx(expected[1]))


def test_line_follow_does_not_apply_without_line_or_reading():
    ns = make_ns()
    layer = LineFollow()
    assert not layer.applies(frame_for(ns))
    ns.put("ground", ground())
    assert not layer.applies(frame_for(ns))


def test_stock_braitenberg_turns_away_from_the_obstacle_side():
    ns = make_ns()
    ns.put("proximity", prox(front_left=0.02, diagonal_left=0.03))
    layer = FrontBraitenbergAvoid(MAX)
    f = frame_for(ns)
    assert layer.applies(f)
    cmd = layer.command(f)
    a_dl, a_fl = 1 - 0.03 / 0.05, 1 - 0.02 / 0.05
    assert cmd.left == pytest.approx(MAX + MAX * (1 * a_dl + 2 * a_fl))
    assert cmd.right == pytest.approx(MAX + MAX * (-1 * a_dl - 2 * a_fl))
    assert cmd.left > cmd.right  # obstacle on the left: turn right


def test_stock_braitenberg_cancels_on_a_symmetric_wall():
    ns = make_ns()
    ns.put(
        "proximity",
        prox(diagonal_left=0.03, front_left=0.02, front_right=0.02, diagonal_right=0.03),
    )
    cmd = FrontBraitenbergAvoid(MAX).command(frame_for(ns))
    assert cmd.left == pytest.approx(cmd.right)  # no turn: drives into it (the thesis's 'stuck')


@pytest.mark.parametrize("side", ["front_left", "front_right", "diagonal_right", "diagonal_left"])
def test_improved_always_turns_left_first(side):
    ns = make_ns()
    ns.put("proximity", prox(**{side: 0.03}))
    cmd = FrontObstacleLeftTurn(MAX).command(frame_for(ns))
    assert (cmd.left, cmd.right) == (pytest.approx(-MAX / 2), pytest.approx(MAX))


def test_improved_falls_back_to_braitenberg_when_both_front_sensors_are_very_close():
    ns = make_ns()
    ns.put("proximity", prox(front_left=0.01, front_right=0.005))
    f = frame_for(ns)
    assert FrontObstacleLeftTurn(MAX).command(f) == FrontBraitenbergAvoid(MAX).command(f)


def test_side_wall_keep_slows_the_wheel_on_the_obstacle_side():
    ns = make_ns()
    ns.put("proximity", prox(right=0.03))
    layer = SideWallKeep(("right",), speed=MAX)
    f = frame_for(ns)
    assert layer.applies(f)
    cmd = layer.command(f)
    assert cmd.left == pytest.approx(MAX)
    assert cmd.right == pytest.approx(MAX - MAX * (1 - 0.03 / 0.05))
    # too close (inside a quarter of the range) or out of range: no correction
    ns.put("proximity", prox(right=0.01))
    assert not layer.applies(frame_for(ns))
    ns.put("proximity", prox(left=0.03))
    assert not layer.applies(frame_for(ns))
    with pytest.raises(ValueError, match="sides"):
        SideWallKeep(("up",))


def test_controller_priorities_match_the_thesis():
    assert [type(layer).__name__ for layer in stock().layers] == [
        "FrontBraitenbergAvoid", "LineFollow", "SideWallKeep", "Cruise",
    ]  # fmt: skip
    assert [type(layer).__name__ for layer in improved().layers] == [
        "FrontObstacleLeftTurn", "LineFollow", "SideWallKeep", "Cruise",
    ]  # fmt: skip
    assert improved().find("SideWallKeep").sides == ("right",)
    assert stock().find("SideWallKeep").sides == ("left", "right")


def test_obstacle_in_front_outranks_the_line():
    ns = make_ns()
    ns.put_many({"proximity": prox(front_right=0.03), "ground": ground(0.1, 0.1, 1.0)})
    ctl = improved()
    ctl.tick(ns)
    assert ctl.active_layer == "FrontObstacleLeftTurn"


def test_load_controller_specs(tmp_path):
    assert load_controller("stock").name == "stock"
    path = tmp_path / "mine.py"
    path.write_text(
        "from puckboard.behaviours import Cruise\n"
        "def make(speed=1.0):\n    return [Cruise(speed)]\n"
    )
    ctl = load_controller(f"{path}:make", speed=0.5)
    assert ctl.layers[0].speed == 0.5
    with pytest.raises(ValueError, match="unknown controller 'nope'"):
        load_controller("nope")
    with pytest.raises(ValueError, match="does not exist"):
        load_controller(str(tmp_path / "missing.py") + ":make")
    with pytest.raises(ValueError, match="has no callable 'nothere'"):
        load_controller(f"{path}:nothere")
    with pytest.raises(ValueError, match="cannot import"):
        load_controller("no_such_module_xyz:make")


def test_each_load_builds_independent_layers():
    a, b = load_controller("improved"), load_controller("improved")
    assert a.layers[0] is not b.layers[0]


def test_controller_rejects_non_layers():
    with pytest.raises(TypeError, match="Layer"):
        Controller(["not a layer"])  # type: ignore[list-item]
    with pytest.raises(ValueError, match="at least one"):
        Controller([])


def test_tree_can_be_printed():
    text = improved().ascii_tree()
    for name in ("improved", "FrontObstacleLeftTurn", "LineFollow", "SideWallKeep", "Cruise"):
        assert name in text


def test_tree_visitors_and_handlers_still_see_every_tick():
    import py_trees

    ctl, high, low = flags_controller()
    ns = make_ns()
    ns.put("flag/low", True)
    ctl.tick(ns)
    assert ctl.tree.count == 1  # the tick is counted even without visitors
    visitor = py_trees.visitors.SnapshotVisitor()
    ctl.tree.visitors.append(visitor)
    seen: list[int] = []
    ctl.tree.add_post_tick_handler(lambda tree: seen.append(tree.count))
    ctl.tick(ns)
    assert seen == [1]
    assert ctl.tree.count == 2
    assert as_behaviour(low).id in visitor.visited and as_behaviour(high).id in visitor.visited
    assert ctl.active_layer == "low"


def test_layers_tick_the_same_with_py_trees_debug_logging_on():
    import py_trees

    def decisions():
        ctl, high, low = flags_controller()
        ns = make_ns()
        out = []
        for flags in ({}, {"low": True}, {"high": True}, {"high": False}, {"low": False}):
            for name, on in flags.items():
                ns.put(f"flag/{name}", on)
            out.append((ctl.tick(ns), ctl.active_layer, [n.status for n in ctl.root.iterate()]))
        return out

    quiet = decisions()
    old = py_trees.logging.level
    py_trees.logging.level = py_trees.logging.Level.DEBUG
    try:
        debug = decisions()
    finally:
        py_trees.logging.level = old
    assert debug == quiet
    assert quiet[2][2][1] == Status.INVALID  # the pre-empted layer (low) was stopped


class Helpers(Layer):
    """A student's layer whose helper methods carry the names py_trees gives its own
    hooks (stop, setup, update, status, parent, ...): they must stay the student's."""

    reads = ("flag/only",)

    def __init__(self):
        super().__init__()
        self.calls: list[str] = []

    def stop(self):
        return WheelCommand(0.0, 0.0)

    def setup(self, speed):
        return WheelCommand(speed, speed)

    def update(self, seen):
        self.calls.append(seen)

    def status(self):
        return "mine"

    def parent(self):
        return "mine"

    def id(self):
        return "mine"

    def initialise(self, x):
        return x

    def terminate(self, x):
        return x

    def tick(self, x):
        return x

    def iterate(self, x):
        return x

    def applies(self, frame):
        flag = bool(frame.value("flag/only", False))
        self.update("flag" if flag else "no flag")
        return flag

    def command(self, frame):
        return self.setup(1.0)


def test_a_layer_may_name_its_helpers_stop_setup_update_status_parent():
    helpers = Helpers()
    ctl = Controller([helpers, Cruise(0.1)])
    ns = make_ns()
    ns.put("flag/only", True)
    assert ctl.tick(ns) == WheelCommand(1.0, 1.0)
    ns.put("flag/only", False)
    assert ctl.tick(ns) == WheelCommand(0.1, 0.1)  # pre-empting it calls none of them
    ns.put("flag/only", True)
    assert ctl.tick(ns) == WheelCommand(1.0, 1.0)
    ctl.reset()
    assert helpers.calls == ["flag", "no flag", "flag"]
    assert (helpers.stop(), helpers.status(), helpers.parent()) == (
        WheelCommand(0.0, 0.0), "mine", "mine",
    )  # fmt: skip
    assert ctl.find("Helpers") is helpers
    assert helpers.parameters() == {}
    assert [n["type"] for n in trace(ctl).nodes] == ["Selector", "Helpers", "Cruise"]


def test_the_arbiter_is_py_trees_own_selector_and_layers_tick_as_py_trees_does():
    """What students read is py_trees used plainly: no subclass with its own tick."""
    import py_trees

    from puckboard.behaviours import Layer

    controller = improved()
    assert type(controller.root) is py_trees.composites.Selector
    assert controller.root.memory is False
    (node,) = {type(as_behaviour(layer)) for layer in controller.every_layer}
    assert node.tick is py_trees.behaviour.Behaviour.tick
    assert node.stop is py_trees.behaviour.Behaviour.stop
    assert not issubclass(Layer, py_trees.behaviour.Behaviour)  # its namespace is its own
