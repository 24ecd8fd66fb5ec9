"""Every layer sees every tick: ``observe`` runs on all layers before the arbiter asks.

py_trees' Selector stops at the first child that applies, so without ``observe`` a layer
below ``LineFollow`` is never called while the line is in view: a layer that wants to
remember where the line was (to search that way once it is lost) would never learn it.
"""

from __future__ import annotations

import numpy as np
import py_trees
import pytest

from puckboard.behaviours import Controller, Cruise, HoldFor, Layer, LineFollow, as_behaviour
from puckboard.blackboard import Blackboard
from puckboard.records import PROX_NAMES, Ground, Proximity, WheelCommand


class Clock:
    t = 0.0

    def __call__(self) -> float:
        return self.t


def ground(left=1.0, centre=1.0, right=1.0):
    v = np.array([left, centre, right])
    return Ground(v, v * 1023)


class LineSideMemory(Layer):
    """Remembers on which side a ground sensor last saw the line; when the line is lost,
    curves towards that side."""

    reads = ("ground",)

    def __init__(self, speed=2.0, ratio=0.5):
        super().__init__()
        self.speed = speed
        self.ratio = ratio
        self.side: str | None = None
        self.observed = 0

    def observe(self, frame):
        self.observed += 1
        g = frame.ground
        if g is None:
            return
        left, _, right = g.dark()
        if left and not right:
            self.side = "left"
        elif right and not left:
            self.side = "right"

    def applies(self, frame):
        g = frame.ground
        return self.side is not None and g is not None and not g.dark().any()

    def command(self, frame):
        slow = self.ratio * self.speed
        if self.side == "left":
            return WheelCommand(slow, self.speed)
        return WheelCommand(self.speed, slow)


def test_a_layer_under_line_follow_remembers_the_side_on_every_tick():
    memory = LineSideMemory()
    ctl = Controller([LineFollow(), memory, Cruise()])
    ns = Blackboard(clock=Clock()).namespace("r")
    drove, remembered = [], []
    for reading in (
        ground(left=0.1),  # the line under the left sensor
        ground(centre=0.1),  # centred: nothing new to learn
        ground(right=0.1),  # now under the right sensor
        ground(),  # lost
    ):
        ns.put("ground", reading)
        ctl.tick(ns)
        drove.append(ctl.active_layer)
        remembered.append(memory.side)
    assert drove == ["LineFollow", "LineFollow", "LineFollow", "LineSideMemory"]
    # learnt while LineFollow drove, though the arbiter never asked this layer
    assert remembered == ["left", "left", "right", "right"]
    assert memory.observed == 4
    assert ctl.last_command == WheelCommand(2.0, 1.0)  # curving right, towards the line


def test_observe_runs_before_arbitration_so_the_same_tick_acts_on_it():
    memory = LineSideMemory()
    ctl = Controller([memory, Cruise()])
    ns = Blackboard(clock=Clock()).namespace("r")
    ns.put("ground", ground(left=0.1))
    ctl.tick(ns)
    assert ctl.active_layer == "Cruise"  # the line is in view: no search
    ns.put("ground", ground())
    assert ctl.tick(ns) == WheelCommand(1.0, 2.0)  # lost: curve left, where it was
    assert ctl.active_layer == "LineSideMemory"


class Counter(Layer):
    """Counts the ticks it observed; never applies."""

    reads = ("proximity",)

    def __init__(self, name):
        super().__init__(name)
        self.frames = []

    def observe(self, frame):
        self.frames.append(frame.time)
        self.seen = frame.proximity

    def applies(self, frame):
        return False

    def command(self, frame):
        return WheelCommand.stop()


def test_every_layer_observes_every_tick_inside_decorators_and_composites():
    clock = Clock()
    held = Counter("held")
    nested = Counter("nested")
    top = Counter("top")
    group = py_trees.composites.Selector("group", memory=False, children=[as_behaviour(nested)])
    ctl = Controller([top, HoldFor(held, 0.5), Cruise(1.0), group], requires=("proximity",))
    ns = Blackboard(clock=clock).namespace("r")
    ns.declare("proximity", max_age=0.1)
    for t in (0.0, 0.05, 0.1):
        clock.t = t
        ns.put("proximity", Proximity(np.full(8, 0.05), np.zeros(8)), stamp=t)
        ctl.tick(ns)
    for layer in (top, held, nested):
        assert layer.frames == [0.0, 0.05, 0.1], layer.name
    assert [n.name for n in ctl.every_layer] == ["top", "held", "Cruise", "nested"]


def test_an_observe_set_on_the_layer_object_is_called_too():
    """Layers that keep Layer's do-nothing observe are not called; one given its own
    observe on the object (not its class) still observes every tick."""
    cruise = Cruise(1.0)
    seen = []
    cruise.observe = lambda frame: seen.append(frame.time)  # type: ignore[method-assign]
    clock = Clock()
    ctl = Controller([cruise])
    ns = Blackboard(clock=clock).namespace("r")
    for t in (0.0, 0.05):
        clock.t = t
        ctl.tick(ns)
    assert seen == [0.0, 0.05]


def test_with_requires_no_layer_observes_until_the_required_key_is_fresh():
    """A student who writes ``requires=("proximity",)`` expects a reading in every call
    of the layers, ``observe`` included: before the first reading (and while it is
    stale) the robot stops and no layer is called, so none has to handle ``None``."""
    clock = Clock()
    layer = Counter("counter")
    ctl = Controller([layer, Cruise(1.0)], requires=("proximity",))
    ns = Blackboard(clock=clock).namespace("r")
    ns.declare("proximity", max_age=0.1)
    ctl.tick(ns)  # no reading yet
    assert (ctl.active_layer, layer.frames) == ("(stale inputs)", [])
    clock.t = 0.05
    ns.put("proximity", Proximity(np.full(8, 0.05), np.zeros(8)), stamp=0.05)
    ctl.tick(ns)
    assert (ctl.active_layer, layer.frames) == ("Cruise", [0.05])
    assert layer.seen is not None
    clock.t = 1.0  # stale again: the robot stops, and nobody is called
    ctl.tick(ns)
    assert (ctl.active_layer, layer.frames) == ("(stale inputs)", [0.05])


def test_without_requires_observe_sees_none_before_the_first_reading():
    layer = Counter("counter")
    ctl = Controller([layer, Cruise(1.0)])
    ns = Blackboard(clock=Clock()).namespace("r")
    ctl.tick(ns)
    assert (ctl.active_layer, layer.frames, layer.seen) == ("Cruise", [0.0], None)


def test_a_layer_that_raises_in_observe_is_named():
    class Broken(Counter):
        def observe(self, frame):
            raise ZeroDivisionError("observe failed")

    ctl = Controller([Cruise(1.0), Broken("broken")])
    ns = Blackboard(clock=Clock()).namespace("r")
    with pytest.raises(ZeroDivisionError, match="observe failed"):
        ctl.tick(ns)
    assert ctl.failed_layer == "broken"


def test_observe_sees_the_same_frame_the_arbiter_decides_on():
    frames = []

    class Spy(Layer):
        reads = ("proximity",)

        def observe(self, frame):
            frames.append(frame)

        def command(self, frame):
            frames.append(frame)
            return WheelCommand(1.0, 1.0)

    ctl = Controller([Spy()])
    ns = Blackboard(clock=Clock()).namespace("r")
    prox = np.full(8, 0.05)
    prox[PROX_NAMES.index("front_left")] = 0.02
    ns.put("proximity", Proximity(prox, np.zeros(8)))
    ctl.tick(ns)
    assert len(frames) == 2 and frames[0] is frames[1]
    assert frames[0].proximity.front_left == pytest.approx(0.02)
