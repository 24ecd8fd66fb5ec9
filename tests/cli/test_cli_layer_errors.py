"""A student's broken layer, run with ``puckboard run --controller file.py:factory``.

What puckboard itself detects (a command that is no finite WheelCommand, an unknown key,
``reads`` as a string, a missing ``super().__init__()``) ends in one line and nothing
else. An exception in the student's own code keeps the traceback of the student's frames
only (not the loop's, the arbiter's or py_trees'), then the line saying where.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from puckboard.cli import main

CONTROLLER = """\
import math

from puckboard.behaviours import Controller, Cruise, Layer
from puckboard.records import WheelCommand


class Wobbly(Layer):
    reads = ("ground",)

    def applies(self, frame):
        return frame.time >= 1.0

    def command(self, frame):
        return {returned}


def make():
    return Controller([Wobbly(), Cruise()])
"""


def write_controller(tmp_path: Path, text: str) -> str:
    path = tmp_path / "wobbly.py"
    path.write_text(text, encoding="utf-8")
    return f"{path}:make"


def run(spec: str) -> int:
    return main(["run", "line-follow", "--controller", spec, "--duration", "3"])


@pytest.mark.parametrize(
    ("returned", "problem"),
    [
        ('"fast"', "command() returned 'fast', a str; it must return WheelCommand(left, right)"),
        ("WheelCommand(math.nan, 1.0)", "WheelCommand.left must be a finite number, got nan"),
        ("WheelCommand(1.0, math.inf)", "WheelCommand.right must be a finite number, got inf"),
        ("(1.0, 2.0)", "command() returned (1.0, 2.0), a tuple; it must return WheelCommand("),
        ("None", "command() returned None (is a 'return' missing?)"),
    ],
    ids=["str", "nan", "inf", "tuple", "None"],
)
def test_a_command_puckboard_refuses_is_one_line(tmp_path, capsys, returned, problem):
    spec = write_controller(tmp_path, CONTROLLER.format(returned=returned))
    assert run(spec) == 1
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("puckboard run: error: robot 'epuck' at t = 1.0"), err
    assert f"in layer 'Wobbly': {problem}" in lines[0]


def test_an_exception_in_the_student_s_code_shows_only_the_student_s_frames(tmp_path, capsys):
    text = CONTROLLER.format(returned="WheelCommand(speed_for(0.0), 1.0)") + (
        "\n\ndef speed_for(distance):\n    return 0.01 / distance\n"
    )
    spec = write_controller(tmp_path, text)
    assert run(spec) == 1
    lines = capsys.readouterr().err.strip().splitlines()
    assert lines[0] == "Traceback (most recent call last):"
    files = [line.split('"')[1] for line in lines if line.lstrip().startswith('File "')]
    assert files == [str(tmp_path / "wobbly.py")] * 2, lines  # command(), then speed_for()
    assert any("return 0.01 / distance" in line for line in lines)
    assert lines[-2] == "ZeroDivisionError: float division by zero"
    assert lines[-1] == (
        "puckboard run: error: robot 'epuck' at t = 1.00 s, in layer 'Wobbly': "
        "ZeroDivisionError: float division by zero"
    )


def test_an_unknown_key_is_one_line_naming_the_robot_s_keys(tmp_path, capsys):
    text = CONTROLLER.format(returned="WheelCommand(1.0, 1.0)").replace('("ground",)', '("grund",)')
    assert run(write_controller(tmp_path, text)) == 1
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(
        "puckboard run: error: robot 'epuck' at t = 0.00 s, in layer 'Wobbly': reads 'grund', "
        "which robot 'epuck' does not have (did you mean 'ground'?); its keys: "
    )
    assert "ns.declare('grund')" in lines[0]


@pytest.mark.parametrize(
    ("change", "says"),
    [
        (
            ('reads = ("ground",)', 'reads = "ground"'),
            "layer 'Wobbly': reads = 'ground' is one string; write a tuple: reads = ('ground',)",
        ),
        (
            ("class Wobbly(Layer):\n", "class Wobbly(Layer):\n    def __init__(self):\n"
             "        self.speed = 1.0\n\n"),
            "Wobbly.__init__ never calls super().__init__(); add super().__init__() as the "
            "first line of Wobbly.__init__",
        ),
    ],
    ids=["reads as a string", "no super().__init__()"],
)  # fmt: skip
def test_a_layer_refused_when_the_controller_is_built_is_one_line(tmp_path, capsys, change, says):
    text = CONTROLLER.format(returned="WheelCommand(1.0, 1.0)").replace(*change)
    assert run(write_controller(tmp_path, text)) == 2
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("puckboard run: error: ")
    assert says in lines[0]
