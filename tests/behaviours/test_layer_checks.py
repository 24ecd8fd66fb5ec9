"""A controller checks its layers once, when it is built, and a layer's ``applies`` must
say yes or no: each mistake a student makes is one line naming the layer and the fix
(issue 35, items 4, 6, 7, 17, 21, 32; issue 36, item 9)."""

from __future__ import annotations

import numpy as np
import pytest
from layer_readings import Clock, ground

from puckboard.behaviours import Controller, Cruise, GoHome, HoldFor, Layer, LineFollow
from puckboard.behaviours.context import Frame
from puckboard.blackboard import Blackboard
from puckboard.errors import LayerError
from puckboard.records import WheelCommand


class NoCommand(Layer):
    def applies(self, frame):
        return True


class Returns(Layer):
    """``applies`` returns whatever it was built with."""

    def __init__(self, value):
        super().__init__()
        self.value = value

    def applies(self, frame):
        return self.value

    def command(self, frame):
        return WheelCommand(1.0, -1.0)


def tick(*layers):
    ns = Blackboard(clock=Clock()).namespace("r")
    ns.put("ground", ground())
    ctl = Controller(list(layers))
    return ctl, ctl.tick(ns)


@pytest.mark.parametrize("layer", [Layer(), NoCommand()], ids=["Layer()", "no command"])
def test_a_layer_without_command_is_refused_when_the_controller_is_built(layer):
    name = type(layer).__name__
    with pytest.raises(LayerError) as caught:
        Controller([layer, Cruise()])
    assert str(caught.value) == (
        f"layer {name!r}: {name} has no command(frame); write one that returns "
        "WheelCommand(left, right), the wheel speeds in rad/s"
    )


def test_an_empty_controller_says_what_to_give_it():
    with pytest.raises(LayerError, match=r"^a Controller needs at least one layer: "):
        Controller([])


def test_a_controller_given_where_its_layers_belong_says_so():
    with pytest.raises(LayerError, match="got the controller 'Arbiter' where its layers"):
        Controller(Controller([Cruise()]))  # type: ignore[arg-type]


def test_the_same_layer_object_twice_is_named_with_the_fix():
    cruise = Cruise()
    with pytest.raises(LayerError) as caught:
        Controller([cruise, cruise])
    assert str(caught.value) == (
        "layer 'Cruise': the same Cruise object is twice in this controller; each place "
        "needs an object of its own: build another (Cruise(...)) for this one"
    )
    follow = LineFollow()
    with pytest.raises(LayerError, match=r"LineFollow object is already in 'HoldFor\("):
        Controller([HoldFor(follow, 0.5), follow])


def test_two_layers_of_one_name_are_refused():
    with pytest.raises(LayerError) as caught:
        Controller([Cruise(), LineFollow(), Cruise()])
    assert "two layers are called 'Cruise'" in str(caught.value)
    assert "name='Cruise2'" in str(caught.value)
    Controller([Cruise(), Cruise(name="Cruise2")])  # named apart: fine


@pytest.mark.parametrize(
    ("value", "says"),
    [
        (None, "applies() returned None (is a 'return' missing?); it must return True or False "
         "(a bool)"),
        ("no", "applies() returned 'no', a str; it must return True or False (a bool)"),
        (1, "applies() returned 1, a int; it must return True or False (a bool)"),
    ],
    ids=["missing return", "str", "int"],
)
def test_applies_must_return_a_bool(value, says):
    with pytest.raises(LayerError) as caught:
        tick(Returns(value), Cruise())
    assert str(caught.value) == f"layer 'Returns': {says}"


@pytest.mark.parametrize("value", [True, np.bool_(True), False, np.bool_(False)])
def test_numpy_s_bool_is_a_bool(value):
    ctl, cmd = tick(Returns(value), Cruise(0.5))
    assert ctl.active_layer == ("Returns" if value else "Cruise")


def test_a_misspelt_frame_attribute_says_what_was_meant():
    frame = Frame(Blackboard(clock=Clock()).namespace("r").snapshot(()))
    with pytest.raises(AttributeError) as caught:
        frame.proximty  # noqa: B018
    assert str(caught.value).startswith(
        "a Frame has no attribute 'proximty'; did you mean frame.proximity?"
    )


def test_reset_lets_every_layer_forget():
    class Remembers(Layer):
        def __init__(self):
            super().__init__()
            self.seen = 0

        def observe(self, frame):
            self.seen += 1

        def reset(self):
            self.seen = 0

        def command(self, frame):
            return WheelCommand.stop()

    remembers = Remembers()
    ctl, _ = tick(HoldFor(remembers, 1.0), Cruise())  # a layer inside a decorator too
    assert remembers.seen == 1
    ctl.reset()
    assert remembers.seen == 0
    home = GoHome()
    home.arrived = True
    home.reset()
    assert not home.arrived
