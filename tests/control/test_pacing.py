"""Pacing a simulated run for people: it waits, it never changes the run."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from puckboard.control.pacing import RealTimePacer


def fake_episode(sim_time, synchronous=True):
    return SimpleNamespace(time=sim_time, loop=SimpleNamespace(synchronous=synchronous))


def test_sleeps_until_simulation_time_matches_speed_times_wall_time():
    slept = []
    wall = iter([100.0, 100.01, 100.5])  # the machine computes much faster than real time
    pacer = RealTimePacer(2.0, clock=lambda: next(wall), sleep=slept.append)
    pacer(fake_episode(0.0))  # the first cycle sets the origin
    pacer(fake_episode(1.0))  # 1 s simulated at 2x = 0.5 s wall; only 0.01 s has passed
    assert slept == [pytest.approx(0.49)]
    pacer(fake_episode(1.0))  # already behind: no wait
    assert len(slept) == 1


def test_a_real_robot_is_never_held_back():
    slept = []
    pacer = RealTimePacer(1.0, clock=lambda: 0.0, sleep=slept.append)
    for t in (0.0, 5.0, 10.0):
        pacer(fake_episode(t, synchronous=False))
    assert slept == []


def test_speed_must_be_positive():
    with pytest.raises(ValueError, match="speed must be a positive multiple of real time"):
        RealTimePacer(0.0)


def test_monitor_paces_by_default_and_refuses_a_bad_speed(monkeypatch, capsys):
    pytest.importorskip("rich")
    from puckboard.cli import main
    from puckboard.control import pacing

    calls = []
    # a frozen wall clock (only inside the pacer): each wait is then exactly the
    # simulated time since the first paced cycle, divided by the speed
    fake_time = SimpleNamespace(perf_counter=lambda: 0.0, sleep=calls.append)
    monkeypatch.setattr(pacing, "time", fake_time)
    assert main(["monitor", "line-follow", "--duration", "1", "--refresh", "100"]) == 0
    assert calls, "a simulated run should have been paced"
    assert max(calls) == pytest.approx(0.95)  # 1 s of simulation after the first 0.05 s step
    calls.clear()
    assert main(["monitor", "line-follow", "--duration", "1", "--speed", "2"]) == 0
    assert max(calls) == pytest.approx(0.475)  # twice real time: half the wait
    assert main(["monitor", "line-follow", "--speed", "-1"]) == 2
    assert "--speed must be a finite number" in capsys.readouterr().err
