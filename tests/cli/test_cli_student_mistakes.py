"""What a student meets on the command line: every command that builds a controller says
the same one line for what puckboard refuses in it, and the command line says which
command did not take an argument (issue 35, items 4, 5, 16, 19, 20, 22, 23)."""

from __future__ import annotations

from pathlib import Path

import pytest

from puckboard.cli import main
from puckboard.cli.run import format_summary

MISTAKES = """\
from puckboard.behaviours import Controller, Cruise, Layer
from puckboard.records import WheelCommand


class Good(Layer):
    def command(self, frame):
        return WheelCommand(1.0, 1.0)


class NoCommand(Layer):
    def applies(self, frame):
        return True


class Never(Layer):
    def applies(self, frame):
        return False

    def command(self, frame):
        return WheelCommand(1.0, 1.0)


def class_not_instance():
    return Controller([Good, Cruise()])


def empty():
    return Controller([])


def no_command():
    return Controller([NoCommand(), Cruise()])


def twice():
    cruise = Cruise()
    return [cruise, cruise]


class NoReturn(Layer):
    def applies(self, frame):
        frame.time > 1.0

    def command(self, frame):
        return WheelCommand(1.0, 1.0)


def no_return():
    return [NoReturn(), Cruise()]


def never():
    return [Never()]
"""


@pytest.fixture
def mistakes(tmp_path: Path) -> Path:
    path = tmp_path / "mistakes.py"
    path.write_text(MISTAKES, encoding="utf-8")
    return path


@pytest.mark.parametrize("command", ["run", "tree", "monitor"])
@pytest.mark.parametrize(
    ("factory", "says"),
    [
        ("class_not_instance", "got the class Good; did you mean Good()?"),
        ("empty", "a Controller needs at least one layer: Controller([Cruise()])"),
        ("no_command", "layer 'NoCommand': NoCommand has no command(frame); write one"),
        ("twice", "layer 'Cruise': the same Cruise object is twice in this controller"),
    ],
)
def test_a_controller_puckboard_refuses_is_one_line_in_every_command(
    mistakes, capsys, command, factory, says
):
    argv = [command, "--controller", f"{mistakes}:{factory}"]
    if command != "tree":
        argv = [command, "line-follow", *argv[1:], "--duration", "0.1"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(f"puckboard {command}: error: {says}"), err


def test_an_applies_without_return_stops_the_run_in_one_line(mistakes, capsys):
    argv = ["run", "line-follow", "--controller", f"{mistakes}:no_return", "--duration", "1"]
    assert main(argv) == 1
    lines = capsys.readouterr().err.strip().splitlines()
    assert lines == [
        "puckboard run: error: robot 'epuck' at t = 0.00 s, in layer 'NoReturn': applies() "
        "returned None (is a 'return' missing?); it must return True or False (a bool)"
    ]


@pytest.mark.parametrize(
    ("argv", "says"),
    [
        (["run", "two-robot-pass", "two-robot-pass-bend"],
         "puckboard run: error: unexpected argument 'two-robot-pass-bend' (one too many); "
         "see 'puckboard run --help'"),
        (["run", "--nosuchflag"],
         "puckboard run: error: no option --nosuchflag; see 'puckboard run --help'"),
        (["run", "--sed", "3"],
         "puckboard run: error: no option --sed (did you mean --seed?); see "
         "'puckboard run --help'"),
        (["emulate", "--device", "x"],
         "puckboard emulate: error: no option --device; see 'puckboard emulate --help'"),
    ],
)  # fmt: skip
def test_what_a_subcommand_does_not_take_is_said_by_the_subcommand(capsys, argv, says):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.strip() == says
    assert "usage: puckboard [-h]" not in err


@pytest.mark.parametrize("command", ["run", "tree"])
def test_a_second_controller_is_refused_pointing_to_sweep(capsys, command):
    argv = [command, "--controller", "improved", "--controller", "stock"]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"puckboard {command}: error: --controller given twice (improved, ")
    assert "puckboard sweep SCENE --controller improved --controller stock" in err


@pytest.mark.parametrize("value", ["nan", "inf", "-inf", "NaN"])
def test_a_non_finite_setting_is_refused_when_read(capsys, value):
    argv = ["run", "line-follow", "--set", f"layer.LineFollow.inner_factor={value}"]
    assert main([*argv, "--duration", "0.1"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == (
        f"puckboard run: error: --set 'layer.LineFollow.inner_factor={value}': "
        f"layer.LineFollow.inner_factor must be a finite number, got {value}"
    )


def test_a_controller_whose_layers_never_apply_is_said(mistakes, caplog):
    argv = ["run", "line-follow", "--controller", f"{mistakes}:never", "--duration", "1"]
    assert main(argv) == 0
    err = caplog.text
    assert "robot 'epuck': no layer of controller 'never' applied in any of its 20 ticks" in err
    assert "check what applies() returns in Never" in err


def test_the_table_never_shows_minus_zero_laps():
    robot = {
        "name": "epuck", "profile": "epuck", "progress_laps": -0.001, "distance_m": 0.01,
        "collisions": 0, "on_line_fraction": 0.0, "obstacles_passed": 0, "passed_other": False,
    }  # fmt: skip
    result = {
        "scenario": "s", "controller": "c", "seed": 0, "sim_time_s": 1.0, "wall_s": 0.1,
        "realtime_factor": 10.0, "steps": 20, "dt_s": 0.05, "robots": [robot],
        "success": True, "failure": None, "failures": [], "events": [],
    }  # fmt: skip

    class Result:
        def to_dict(self):
            return result

    row = next(line for line in format_summary(Result()).splitlines() if line.startswith("epuck"))
    assert row.split()[2] == "0.00"
    robot["progress_laps"] = -0.25  # a robot that really went back says so
    row = next(line for line in format_summary(Result()).splitlines() if line.startswith("epuck"))
    assert row.split()[2] == "-0.25"


def test_a_run_on_a_robot_does_not_call_its_time_simulated():
    result = {
        "scenario": "line-follow", "controller": "c", "seed": 0, "sim_time_s": 15.0,
        "wall_s": 15.1, "realtime_factor": 1.0, "steps": 300, "dt_s": 0.05, "robots": [],
        "success": True, "failure": None, "failures": [], "events": [],
    }  # fmt: skip

    class Result:
        def to_dict(self):
            return result

    first = format_summary(Result(), simulated=False).splitlines()[0]
    assert first.endswith("15.0 s on the robot (300 steps of 50 ms)")
    assert "simulated" not in first
    assert "15.0 s simulated in 15.10 s" in format_summary(Result()).splitlines()[0]
