import io

import pytest
from rich.console import Console
from viz_standin import StandInEpisode

from puckboard.blackboard import Blackboard
from puckboard.records import Ground, Pose, Proximity, WheelCommand
from puckboard.viz.monitor import SensorMonitor, format_value


def test_monitor_renders_every_key_with_age_and_rate_without_a_terminal():
    ep = StandInEpisode()
    out = io.StringIO()
    console = Console(file=out, width=140)
    assert not console.is_terminal
    monitor = SensorMonitor.for_episode(ep, console=console).attach(ep)
    ep.run(2.0)
    printed = out.getvalue()
    assert "\x1b[" not in printed  # no escape codes in a file or pipe
    for word in ("red", "blue", "proximity", "ground", "pose", "command/layer", "LineFollow"):
        assert word in printed
    # every key was updated once per 50 ms cycle: 20 Hz
    assert monitor.rate("red/proximity") == pytest.approx(20.0)
    assert monitor.rate("blue/command/wheels") == pytest.approx(20.0)
    text = monitor.render_text()
    assert "front_left 3.0" in text  # the fake's front-left reading, named, in cm
    assert "20.0" in text


def test_stale_keys_show_a_falling_rate():
    now = {"t": 0.0}
    board = Blackboard(clock=lambda: now["t"])
    board.declare("r/ground", max_age=0.2)
    monitor = SensorMonitor(board, ["r"], console=Console(file=io.StringIO()))
    for k in range(10):
        now["t"] = k * 0.1
        board.put("r/ground", Ground([1, 1, 1], [1000, 1000, 1000]), stamp=now["t"])
        monitor.sample()
    assert monitor.rate("r/ground") == pytest.approx(10.0)
    now["t"] = 1.9  # the sensor stopped 1 s ago
    monitor.sample()
    assert monitor.rate("r/ground", stale=True) < 6.0
    assert "1.00" in monitor.render_text()  # its age


def test_values_are_formatted_with_names_and_units():
    assert format_value(Proximity.nothing()) == "nothing within 5 cm"
    assert format_value(WheelCommand(1, -1)) == "L +1.00  R -1.00 rad/s"
    assert "θ  +90.0°" in format_value(Pose(0, 0, 1.5707963, ground_truth=True))
    assert format_value(Ground([0.1, 0.5, 0.9], [0, 0, 0])) == "L 0.10  C 0.50  R 0.90"


def test_monitor_cli_prints_a_plain_table_when_piped(capsys):
    from puckboard.cli import main

    assert main(["monitor", "two-robot-pass", "--duration", "1"]) == 0
    out = capsys.readouterr().out
    assert "\x1b[" not in out
    for word in ("left", "right", "proximity", "ground", "command/layer", "rate (Hz)"):
        assert word in out
    assert main(["monitor", "no-such-scene"]) == 2


def test_monitor_still_keeps_the_wheels_at_zero(capsys):
    from puckboard.cli import main

    assert main(["monitor", "line-follow", "--still", "--duration", "0.5"]) == 0
    out = capsys.readouterr().out
    assert "L +0.00  R +0.00 rad/s" in out
    assert "Still" in out
