"""``--set layer.<Layer>.<parameter>=VALUE`` takes the parameter's own type: a command
line gives text, and the text "no" is true in Python."""

from __future__ import annotations

import pytest

from puckboard.behaviours import Controller, Layer, improved
from puckboard.behaviours.overrides import apply_layer_overrides
from puckboard.cli import main
from puckboard.scenario.overrides import parse_overrides


class Tunable(Layer):
    """A layer with one parameter of every number type."""

    def __init__(self) -> None:
        super().__init__()
        self.enabled = True
        self.repeats = 3
        self.gain = 0.5

    def command(self, frame):  # pragma: no cover - never ticked here
        return None


def tuned(*settings: str) -> Controller:
    controllers = {"robot": Controller([Tunable()], name="tunable")}
    apply_layer_overrides(controllers, parse_overrides(list(settings)))
    return controllers["robot"]


@pytest.mark.parametrize(
    ("text", "expected"),
    [("no", False), ("off", False), ("0", False), ("False", False), ("false", False),
     ("yes", True), ("ON", True), ("1", True), ("true", True)],
)  # fmt: skip
def test_a_boolean_parameter_takes_the_usual_words(text, expected):
    controllers = {"robot": improved()}
    apply_layer_overrides(controllers, parse_overrides([f"layer.LineFollow.recovery={text}"]))
    assert controllers["robot"].find("LineFollow").recovery is expected


@pytest.mark.parametrize("text", ["maybe", "2", "0.5", "nein"])
def test_a_boolean_parameter_refuses_anything_else_and_says_it_is_a_boolean(text):
    with pytest.raises(ValueError, match=r"is a boolean: use true/false, yes/no, on/off or 1/0"):
        tuned(f"layer.Tunable.enabled={text}")


def test_numbers_take_the_type_of_the_parameter():
    layer = tuned("layer.Tunable.repeats=5.0", "layer.Tunable.gain=2").find("Tunable")
    assert layer.repeats == 5 and type(layer.repeats) is int
    assert layer.gain == 2.0 and type(layer.gain) is float


@pytest.mark.parametrize(
    ("setting", "message"),
    [
        ("layer.Tunable.repeats=2.5", r"needs a whole number \(the parameter is int\), got 2.5"),
        ("layer.Tunable.repeats=many", r"needs a whole number \(the parameter is int\)"),
        ("layer.Tunable.gain=true", r"needs a number \(the parameter is float\), got True"),
        ("layer.Tunable.gain=high", r"needs a number \(the parameter is float\), got 'high'"),
    ],
)
def test_numbers_refuse_other_values_naming_the_type(setting, message):
    with pytest.raises(ValueError, match=message):
        tuned(setting)


def test_run_refuses_a_boolean_it_cannot_read_in_one_line(capsys):
    assert main(["run", "--set", "layer.LineFollow.recovery=maybe"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "'layer.LineFollow.recovery' is a boolean" in err and "got 'maybe'" in err
