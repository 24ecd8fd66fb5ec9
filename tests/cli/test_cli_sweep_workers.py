"""``sweep --workers``: no more worker processes than episodes, a warning above the
CPUs, and a wall time that counts the workers' start-up (issue 30, round 4, item 9)."""

from __future__ import annotations

import re
import time

import pytest

import puckboard.sweep
from puckboard.cli import main

SMALL = ["sweep", "--seeds", "0:2", "--duration", "0.2", "-q"]


@pytest.fixture
def started(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """The worker counts of the local executors the command creates."""
    counts: list[int] = []
    base = puckboard.sweep.LocalExecutor

    class Counted(base):  # type: ignore[misc, valid-type]
        def __init__(self, workers: int | None = None) -> None:
            super().__init__(workers)
            counts.append(self.workers)

    monkeypatch.setattr(puckboard.sweep, "LocalExecutor", Counted)
    return counts


def test_workers_are_capped_at_the_episodes(started, capsys):
    assert main([*SMALL, "--workers", "200"]) == 0
    assert started == [2]
    assert "warning" not in capsys.readouterr().err  # 2 workers are not above the CPUs here


def test_more_workers_than_cpus_is_said(started, monkeypatch, capsys):
    monkeypatch.setattr(puckboard.sweep.executors, "available_cpus", lambda: 1)
    assert main([*SMALL, "--workers", "2"]) == 0
    assert started == [2]
    err = capsys.readouterr().err
    assert "warning: --workers 2 is more than this machine's 1 CPUs" in err


def test_the_wall_time_counts_the_workers_start_up(monkeypatch, capsys):
    base_start = puckboard.sweep.LocalExecutor.start

    def slow_start(self):  # a start-up the report must not leave out
        time.sleep(0.6)
        return base_start(self)

    monkeypatch.setattr(puckboard.sweep.LocalExecutor, "start", slow_start)
    base_run = puckboard.sweep.run_sweep

    def run_sweep(*args, **kwargs):  # the sweep's own clock, which starts after the workers
        result = base_run(*args, **kwargs)
        result.wall_s = 0.0
        return result

    monkeypatch.setattr(puckboard.sweep, "run_sweep", run_sweep)
    assert main([*SMALL, "--workers", "1"]) == 0
    header = capsys.readouterr().out.splitlines()[0]
    seconds = float(re.search(r", ([0-9.]+) s$", header).group(1))
    assert seconds >= 0.6, header
