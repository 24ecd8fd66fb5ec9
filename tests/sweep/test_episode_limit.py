"""``--episode-timeout`` stops any layer on local workers: the process running the
episode is killed and replaced, that episode becomes an error row of kind ``timeout``,
and everything else runs (issue 44, item 2: a layer asleep in ``time.sleep(3600)`` held a
sweep past 75 s with a 5 s limit, and a transfer at "0 of 3 episodes" at 100 s).

Each command runs in a process of its own with a generous ``timeout``: a regression makes
the test fail after that wait, never hang the suite. Nothing here sleeps to wait for
something; the layers under test sleep, and the short limits stop them.
"""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path

import pytest
from sweep_helpers import DURATION, PATIENCE_S

from puckboard.sweep import InlineExecutor, LocalExecutor, SweepPlan, run_sweep
from puckboard.sweep.options import RunOptions

pytestmark = pytest.mark.slow

SLEEPER = """
import time
from puckboard.behaviours import Controller, Cruise

class Nap(Cruise):
    def command(self, frame):
        time.sleep(3600)  # blocked in C: nothing inside the process can stop it

def make_controller(speed=2.0):
    return Controller([Nap(speed)], name="nap")
"""

#: The first episode to run, in any process, does ``WHAT``; every other one drives.
FIRST_EPISODE = """
import os, time
from pathlib import Path
from puckboard.behaviours import Controller, Cruise

MARK = Path({marker!r})

class Once(Cruise):
    def command(self, frame):
        if not MARK.exists():
            MARK.touch()
            {what}
        return super().command(frame)

def make_controller():
    return Controller([Once()], name="once")
"""


def puckboard(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "puckboard", *args],
        cwd=cwd, capture_output=True, text=True, timeout=PATIENCE_S,
    )  # fmt: skip


def rows(path: Path) -> list[dict[str, str]]:
    with path.open(newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def stopped(row: dict[str, str]) -> bool:
    return (
        row["failure"] == "error"
        and row["error_kind"] == "timeout"
        and "wall-clock limit of 1 s and its process was stopped" in row["error"]
    )


@pytest.fixture
def sleeper(tmp_path: Path) -> str:
    (tmp_path / "nap.py").write_text(SLEEPER)
    return "nap.py:make_controller"


def test_a_sweep_stops_a_sleeping_layer_and_grades_the_others(tmp_path, sleeper):
    done = puckboard(
        "sweep", "line-follow", "--controller", sleeper, "--controller", "stock",
        "--seeds", "0:2", "--duration", "1", "--workers", "1", "--episode-timeout", "1",
        "--quiet", "--out", "runs.csv", cwd=tmp_path,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    by_controller: dict[str, list[dict[str, str]]] = {}
    for row in rows(tmp_path / "runs.csv"):
        by_controller.setdefault(row["controller"], []).append(row)
    assert len(by_controller[sleeper]) == 2 and all(map(stopped, by_controller[sleeper]))
    assert [r["error"] for r in by_controller["stock"]] == ["", ""]
    assert all(float(r["sim_time_s"]) > 0 for r in by_controller["stock"])
    assert "2 of 4 episodes ended in error (2 timeout;" in done.stderr


@pytest.mark.parametrize(
    "command",
    [
        ["transfer", "line-follow", "--seeds", "0:1", "--families", "noise"],
        ["sensitivity", "line-follow", "--profile", "epuck", "--fields", "ir_gain",
         "--values", "2", "--seeds", "0:1"],
    ],
    ids=["transfer", "sensitivity"],
)  # fmt: skip
def test_transfer_and_sensitivity_stop_a_sleeping_layer(tmp_path, sleeper, command):
    done = puckboard(
        *command, "--controller", sleeper, "--duration", "1", "--workers", "1",
        "--episode-timeout", "1", "--quiet", "--out", "runs.csv", cwd=tmp_path,
    )  # fmt: skip
    assert done.returncode == 1, done.stderr  # every episode ended in error: status 1
    ran = rows(tmp_path / "runs.csv")
    assert len(ran) >= 3 and all(map(stopped, ran))
    assert f"{len(ran)} of {len(ran)} episodes ended in error ({len(ran)} timeout;" in done.stderr


def test_tuning_stops_a_sleeping_layer(tmp_path, sleeper):
    done = puckboard(
        "tune", "line-follow", "--controller", sleeper, "--param", "controller.speed=1:2",
        "--seeds", "0:1", "--validate", "1:2", "--trials", "1", "--duration", "1",
        "--workers", "1", "--episode-timeout", "1", "--quiet", "--json", cwd=tmp_path,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    study = json.loads(done.stdout)
    assert [c["successes"] for c in study["design"] + study["validation"]] == [0, 0]


@pytest.mark.parametrize(
    ("what", "kind", "said"),
    [
        ("time.sleep(3600)", "timeout", "ran past its wall-clock limit of 1 s"),
        ("os._exit(7)", "exited", "its process exited with status 7"),
    ],
)
def test_the_rest_of_a_batch_runs_after_its_episode_is_lost(tmp_path, what, kind, said):
    """One batch of three episodes on one worker: the first to run is lost with its
    process; the other two run on a fresh one and give the rows they give anywhere."""
    marker = tmp_path / "once"
    controller = tmp_path / "once.py"
    controller.write_text(FIRST_EPISODE.format(marker=str(marker), what=what))
    plan = SweepPlan.from_specs(
        "line-follow",
        controllers=[f"{controller.as_posix()}:make_controller"],
        seeds="0:3",
        fixed={"duration": DURATION},
    )
    with LocalExecutor(workers=1) as executor:
        options = RunOptions(executor=executor, batch_size=3, episode_timeout=1)
        result = run_sweep(plan, "line-follow", options)
    assert result.ran == 3
    lost = [r for r in result.rows if r["error"]]
    assert len(lost) == 1 and lost[0]["error_kind"] == kind and said in lost[0]["error"]
    assert result.error_kinds() == {kind: 1}

    # the others, as this process runs them (the marker is there now: no episode is lost)
    again = run_sweep(plan, "line-follow", RunOptions(executor=InlineExecutor()))
    expected = {r["key"]: r for r in again.rows}
    timing = {"wall_s", "realtime_factor"}
    for row in result.rows:
        if row is not lost[0]:
            assert {k: v for k, v in row.items() if k not in timing} == {
                k: v for k, v in expected[row["key"]].items() if k not in timing
            }


def test_a_dask_cluster_stops_a_sleeping_layer_on_its_process(tmp_path):
    """Where its workers may start processes (the local cluster of our own is started so),
    a Dask worker runs each batch in a host process of its own, which it kills as a
    local sweep does."""
    pytest.importorskip("dask.distributed")
    from puckboard.sweep import DaskExecutor

    (tmp_path / "nap.py").write_text(SLEEPER)
    plan = SweepPlan.from_specs(
        "line-follow",
        controllers=[f"{(tmp_path / 'nap.py').as_posix()}:make_controller", "stock"],
        seeds="0:2",
        fixed={"duration": DURATION},
    )
    with DaskExecutor(local_workers=1) as executor:
        assert executor.stops_processes
        result = run_sweep(plan, "line-follow", RunOptions(executor=executor, episode_timeout=1))
    lost = [r for r in result.rows if r["error"]]
    assert len(lost) == 2 and all(r["controller"] == plan.controllers[0] for r in lost)
    assert all(r["error_kind"] == "timeout" and "process was stopped" in r["error"] for r in lost)
    expected = run_sweep(
        SweepPlan(
            "line-follow", controllers=("stock",), seeds=range(2), fixed={"duration": DURATION}
        ),
        "line-follow",
        RunOptions(executor=InlineExecutor()),
    )
    timing = {"wall_s", "realtime_factor"}
    kept = sorted(
        (r["key"], {k: v for k, v in r.items() if k not in timing}.items())
        for r in result.rows
        if not r["error"]
    )
    assert kept == sorted(
        (r["key"], {k: v for k, v in r.items() if k not in timing}.items()) for r in expected.rows
    )
