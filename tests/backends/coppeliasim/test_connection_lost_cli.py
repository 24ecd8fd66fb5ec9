"""A ``puckboard serve`` that goes away mid-run: one line saying what was lost, when, and
whether the wheels were stopped; status 1, no traceback."""

from __future__ import annotations

import logging

import pytest
from coppeliasim_support import stop_server

from puckboard.backends.coppeliasim.factory import open_coppeliasim
from puckboard.cli import main
from puckboard.control.loop import ControlLoop

pytestmark = pytest.mark.network

LOST_AT_CYCLE = 20


def stop_at_cycle(monkeypatch, cycle, stop):
    """Call ``stop()`` (the server going away) just before control cycle ``cycle``."""
    original = ControlLoop.cycle

    def cycle_then_maybe_stop(loop):
        if loop.cycles == cycle:
            stop()
        original(loop)

    monkeypatch.setattr(ControlLoop, "cycle", cycle_then_maybe_stop)


@pytest.mark.parametrize("command", ["run", "monitor"])
def test_a_server_that_goes_away_mid_run_ends_in_one_line(
    server, monkeypatch, capsys, caplog, command
):
    if command == "monitor":
        pytest.importorskip("rich")
    stop_at_cycle(monkeypatch, LOST_AT_CYCLE, lambda: stop_server(server))
    # silence is noticed after the link's timeout (5 s by default); the subject here is
    # what the command says once it is, so the test waits 1 s instead
    monkeypatch.setitem(open_coppeliasim.__kwdefaults__, "timeout", 1.0)
    argv = [command, "--backend", "coppeliasim", "--port", str(server.port), "--duration", "60"]
    if command == "monitor":
        argv += ["--speed", "0"]
    with caplog.at_level(logging.WARNING):
        assert main(argv) == 1
    err = capsys.readouterr().err
    assert "Traceback" not in err and "Traceback" not in caplog.text
    line = err.strip().splitlines()[-1]
    assert line.startswith(f"puckboard {command}: error: the coppeliasim connection was lost")
    # the last step that completed: cycle 20 of 50 ms
    assert f"t = {LOST_AT_CYCLE * 0.05:.2f} s of simulated time" in line
    assert "no stop command reached 'left', 'right'" in line  # the server was gone
    assert f"127.0.0.1:{server.port}" in line  # what was lost
    # the robots' own warnings that the wheels could not be stopped say nothing more
    assert len(err.strip().splitlines()) == 1, err
    assert "could not" not in caplog.text
