"""The mistakes a student makes writing a layer end in one line that says what to write.

Each of these used to surface as something else: py_trees' "no attribute 'parent'", a
``reads`` split into letters, a key misspelt for ever reading as "no value", a bare
``TypeError`` or ``ValueError`` from deep inside the loop.
"""

from __future__ import annotations

import math

import pytest

from puckboard.backends import FakeAdapter
from puckboard.behaviours import (
    Controller,
    Cruise,
    HoldFor,
    Layer,
    LineFollow,
    as_behaviour,
    load_controller,
)
from puckboard.blackboard import Blackboard
from puckboard.errors import LayerError
from puckboard.estimation.knowledge import KnowledgeSource
from puckboard.records import WheelCommand


class Forgetful(Layer):
    def __init__(self, speed=1.0):
        self.speed = speed  # no super().__init__()

    def command(self, frame):
        return WheelCommand(self.speed, self.speed)


@pytest.mark.parametrize("wrap", [False, True], ids=["layer", "inside HoldFor"])
def test_a_layer_without_super_init_is_named_with_the_line_to_add(wrap):
    with pytest.raises(LayerError) as caught:
        Controller([HoldFor(Forgetful(), 0.5) if wrap else Forgetful(), Cruise()])
    message = str(caught.value)
    assert "\n" not in message
    assert "Forgetful.__init__ never calls super().__init__()" in message
    assert "add super().__init__() as the first line of Forgetful.__init__" in message


class Reads(Layer):
    def __init__(self, reads):
        super().__init__()
        self.reads = reads

    def command(self, frame):
        return WheelCommand(1.0, 1.0)


def test_reads_given_as_one_string_is_refused_when_the_controller_is_built():
    with pytest.raises(LayerError, match=r"reads = 'proximity' is one string; write a tuple: "
                       r"reads = \('proximity',\)"):  # fmt: skip
        Controller([Reads("proximity"), Cruise()])
    with pytest.raises(LayerError, match="as text, got 3"):
        Controller([Reads(("ground", 3)), Cruise()])
    with pytest.raises(TypeError, match=r"requires=\('proximity',\)"):
        Controller([Cruise()], requires="proximity")


def test_an_unknown_key_is_refused_at_the_first_tick_naming_the_robot_s_keys():
    robot = FakeAdapter()
    ctl = Controller([Reads(("proximty",)), Cruise()])
    robot.sense_all()
    with pytest.raises(LayerError) as caught:
        ctl.tick(robot.ns)
    message = str(caught.value)
    assert message.startswith("layer 'Reads': reads 'proximty', which robot 'epuck' does not")
    assert "did you mean 'proximity'?" in message
    assert "its keys: acceleration, camera, " in message and ", proximity, " in message
    assert "ns.declare('proximty')" in message  # how to read a key of one's own
    assert ctl.failed_layer == "Reads"
    with pytest.raises(LayerError, match="controller 'Arbiter' requires 'proximty'"):
        Controller([Cruise()], requires=("proximty",)).tick(robot.ns)


def test_keys_declared_written_or_derived_are_known():
    board = Blackboard(clock=lambda: 0.0)
    ns = board.namespace("r")
    ns.declare("mission/goal")
    ns.put("mission/speed", 1.0)

    class Derived(KnowledgeSource):
        reads = ("encoders",)
        writes = ("percept/derived",)

        def compute(self, inputs):
            return None  # nothing written yet: the key is known all the same

    Derived(ns)
    ctl = Controller([Reads(("mission/goal", "mission/speed", "percept/derived", "camera"))])
    assert ctl.tick(ns) == WheelCommand(1.0, 1.0)


def test_a_knowledge_source_keeps_the_settings_of_a_key_declared_before():
    ns = Blackboard(clock=lambda: 0.0).namespace("r")
    ns.declare("percept/derived", max_age=0.1)

    class Derived(KnowledgeSource):
        reads = ("encoders",)
        writes = ("percept/derived",)

    Derived(ns)
    ns.put("percept/derived", 1.0, stamp=-1.0)
    assert ns.snapshot(["percept/derived"]).status("percept/derived") == "stale"


class Returns(Layer):
    reads = ("proximity",)

    def __init__(self, value):
        super().__init__()
        self.value = value

    def command(self, frame):
        return self.value()


@pytest.mark.parametrize(
    ("value", "says"),
    [
        (lambda: "fast", "command() returned 'fast', a str; it must return WheelCommand(left,"),
        (lambda: (1.0, 2.0), "command() returned (1.0, 2.0), a tuple; it must return"),
        (lambda: None, "command() returned None (is a 'return' missing?)"),
        (lambda: math.nan, "command() returned nan, a float"),
        (lambda: WheelCommand(math.nan, 1.0), "WheelCommand.left must be a finite number, got nan"),
        (
            lambda: WheelCommand(1.0, -math.inf),
            "WheelCommand.right must be a finite number, got -inf",
        ),
    ],
    ids=["str", "tuple", "None", "bare nan", "nan", "inf"],
)
@pytest.mark.parametrize("wrap", [False, True], ids=["layer", "held"])
def test_a_command_that_is_no_finite_wheel_command_is_a_layer_error(value, says, wrap):
    robot = FakeAdapter()
    robot.sense_all()
    layer = Returns(lambda: WheelCommand(1.0, 1.0))
    ctl = Controller([HoldFor(layer, 1.0) if wrap else layer, Cruise()])
    ctl.tick(robot.ns)
    layer.value = value
    if wrap:  # the hold keeps asking the layer for its command after it stops applying
        layer.applies = lambda frame: False  # type: ignore[method-assign]
    with pytest.raises(LayerError) as caught:
        ctl.tick(robot.ns)
    assert str(caught.value).startswith("layer 'Returns': ")
    assert says in caught.value.problem
    assert ctl.failed_layer == "Returns"


class Misread(Layer):
    """Reads through ``how`` what its ``reads`` may not declare."""

    def __init__(self, reads, how):
        super().__init__()
        self.reads = reads
        self.how = how

    def applies(self, frame):
        return self.how(frame) is not None

    def command(self, frame):
        return WheelCommand(1.0, 1.0)


@pytest.mark.parametrize(
    ("reads", "how", "says"),
    [
        (
            ("proximity",),
            lambda frame: frame.value("proximty"),
            "reads 'proximty', which it does not declare in reads = ('proximity',) "
            "(did you mean 'proximity'?)",
        ),
        (
            ("ground",),
            lambda frame: frame.proximity,
            "reads 'proximity', which it does not declare in reads = ('ground',); "
            "to read it, add it: reads = ('ground', 'proximity')",
        ),
        (
            ("ground",),
            lambda frame: frame.value("proximty"),
            "reads 'proximty', which it does not declare in reads = ('ground',) "
            "(did you mean 'proximity'?); to read it, add it: reads = ('ground', 'proximity')",
        ),
        (
            (),
            lambda frame: frame.value("my/flag"),
            "reads 'my/flag', which it does not declare in reads = (); "
            "to read it, add it: reads = ('my/flag',)",
        ),
    ],
    ids=["misspelt", "forgotten", "misspelt and forgotten", "nothing declared"],
)
def test_reading_a_key_the_layer_does_not_declare_names_layer_key_and_reads(reads, how, says):
    """A key outside ``reads`` used to read as None (the snapshot holds only the keys
    some layer declared), so the layer never applied and Cruise drove."""
    robot = FakeAdapter()
    robot.sense_all()
    controller = Controller([Misread(reads, how), Cruise()])
    with pytest.raises(LayerError) as caught:
        controller.tick(robot.ns)
    assert str(caught.value) == f"layer 'Misread': {says}"
    assert caught.value.layer == "Misread" and controller.failed_layer == "Misread"
    robot.close()


def test_a_layer_reads_every_key_it_declares_and_another_layer_s_only_if_declared():
    seen = {}

    class Both(Layer):
        reads = ("ground", "proximity")

        def applies(self, frame):
            seen["both"] = (frame.ground is not None, frame.proximity is not None)
            return False

        def command(self, frame):
            return WheelCommand.stop()

    robot = FakeAdapter()
    robot.sense_all()
    controller = Controller([Both(), Misread(("ground",), lambda f: f.ground), Cruise()])
    controller.tick(robot.ns)
    assert seen["both"] == (True, True)
    assert controller.active_layer == "Misread"  # its ground reading is there
    robot.close()


# -- what the wrong thing given to a controller says -----------------------------------------
def classes_not_objects():
    return Controller([LineFollow, Cruise])


def a_list_of_classes():
    return [LineFollow, Cruise]


def needs_speed(speed):
    return Controller([Cruise(speed)])


@pytest.mark.parametrize("factory", [classes_not_objects, a_list_of_classes])
def test_layers_given_as_classes_say_which_object_was_meant(factory):
    """This used to read "controller ... does not accept parameters {}"."""
    with pytest.raises(
        LayerError, match=r"^got the class LineFollow; did you mean LineFollow\(\)\?$"
    ):
        load_controller(factory)


def test_hold_for_given_a_class_says_which_object_was_meant():
    with pytest.raises(LayerError, match=r"did you mean LineFollow\(\)\?$"):
        HoldFor(LineFollow, 0.5)


def test_a_factory_that_needs_an_argument_names_it():
    with pytest.raises(LayerError) as caught:
        load_controller(needs_speed)
    message = str(caught.value)
    assert "needs_speed() needs the argument 'speed'" in message
    assert "needs_speed(speed=...)" in message


@pytest.mark.parametrize("wrap", [False, True], ids=["layer", "inside HoldFor"])
def test_ticked_outside_a_controller_says_how_to_run_it(wrap):
    """py_trees can tick a layer's node (or a HoldFor) in a tree of its own, where no
    controller takes a snapshot: one check, the same line for both."""
    import py_trees

    node = HoldFor(Cruise(), 0.5) if wrap else as_behaviour(Cruise())
    tree = py_trees.trees.BehaviourTree(node)
    tree.setup()
    with pytest.raises(RuntimeError) as caught:
        tree.tick()
    assert str(caught.value) == (  # HoldFor ticks its layer first: the layer is named
        "'Cruise' was ticked outside a Controller; build a Controller from your layers "
        "and call controller.tick()"
    )
