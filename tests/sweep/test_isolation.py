"""Several plans as one run, each controller's episodes in processes of their own."""

from __future__ import annotations

import dataclasses

import pytest
from sweep_helpers import DURATION

from puckboard.sweep import InlineExecutor, LocalExecutor, SweepPlan
from puckboard.sweep.host import Isolation
from puckboard.sweep.options import RunOptions
from puckboard.sweep.run import run_sweeps

#: Notes, in the folder it runs in, the process that runs each of its episodes.
WHO_RUNS_ME = """
import os
from pathlib import Path
from puckboard.behaviours import improved

def make_controller():
    with Path("pids.txt").open("a") as f:
        f.write(f"{os.getpid()}\\n")
    print("built one")  # goes to the isolation's output file
    return improved()
"""


@pytest.mark.slow
def test_each_isolation_runs_in_processes_and_folders_of_its_own(
    tmp_path, short_scene, monkeypatch
):
    names = ["alice", "bob", "carl"]
    for name in names:
        (tmp_path / f"{name}.py").write_text(WHO_RUNS_ME)
    specs = {name: f"{(tmp_path / f'{name}.py').as_posix()}:make_controller" for name in names}
    bend = dataclasses.replace(short_scene, name="line-follow-again")
    plans = [
        SweepPlan(
            scene.name, controllers=tuple(names), seeds=range(2), fixed={"duration": DURATION}
        )
        for scene in (short_scene, bend)
    ]

    def isolation(name: str) -> Isolation:
        return Isolation(
            name, workdir=str(tmp_path / "work" / name), output=str(tmp_path / f"{name}.out")
        )

    with LocalExecutor(workers=2) as executor:
        results = run_sweeps(
            list(zip(plans, (short_scene, bend))),
            RunOptions(executor=executor, batch_size=1),
            isolation=isolation,
            aliases=specs,
        )
    monkeypatch.chdir(tmp_path / "work")  # where this process's own episodes write
    expected = run_sweeps(
        list(zip(plans, (short_scene, bend))), RunOptions(executor=InlineExecutor()), aliases=specs
    )
    for got, want in zip(results, expected):
        assert got.ran == want.ran == 6
        timing = {"wall_s", "realtime_factor"}
        assert sorted(
            (r["key"], {k: v for k, v in r.items() if k not in timing}.items()) for r in got.rows
        ) == sorted(
            (r["key"], {k: v for k, v in r.items() if k not in timing}.items()) for r in want.rows
        )
        assert {r["controller"] for r in got.rows} == set(names)  # rows name them as planned
    pids = {
        name: set((tmp_path / "work" / name / "pids.txt").read_text().split()) for name in names
    }
    # a controller built per robot, 4 episodes each, every one in its own folder
    built = 4 * len(short_scene.robots)
    assert all(
        len((tmp_path / "work" / n / "pids.txt").read_text().split()) == built for n in names
    )
    for a in names:
        for b in names:
            if a != b:
                assert not pids[a] & pids[b], "two submissions shared a process"
    assert (tmp_path / "alice.out").read_text().count("built one") == built
