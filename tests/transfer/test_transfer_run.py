"""Running a transfer report: one sweep per scene, stopped reports keep what ran."""

from __future__ import annotations

import dataclasses

from sweep_helpers import DURATION, CountingExecutor

from puckboard.scenario.scenefile import load_scene
from puckboard.sweep import InlineExecutor, open_store
from puckboard.sweep.options import RunOptions
from puckboard.transfer import choose_families, run_transfer_plan, transfer_plan
from puckboard.transfer import run as transfer_run

FIRST = dataclasses.replace(load_scene("line-follow"), duration=DURATION)
SECOND = dataclasses.replace(FIRST, name="line-follow-again")
SCENES = {s.name: s for s in (FIRST, SECOND)}


def plan():
    return transfer_plan(
        [FIRST, SECOND], controllers=["stock"], profiles={s: ["epuck"] for s in SCENES},
        seeds=range(1), families=choose_families(["noise"]),
    )  # fmt: skip


def test_a_stopped_report_starts_no_further_scene_and_keeps_what_ran(tmp_path):
    with open_store(tmp_path / "runs.csv") as store:
        result = run_transfer_plan(
            plan(),
            SCENES,
            RunOptions(executor=CountingExecutor(interrupt_after=1), store=store, batch_size=1),
        )
    assert result.interrupted and result.ran == 1
    assert [s.ran for s in result.sweeps] == [1, 0]
    first, second = result.cells
    assert sum(p.episodes for p in first.radii[0].grid) == 1  # the grid holds every point
    assert second.design.stats is None and all(b.stats is None for b in second.families)
    with open_store(tmp_path / "runs.csv") as store:
        again = run_transfer_plan(
            plan(), SCENES, RunOptions(executor=InlineExecutor(), store=store)
        )
    assert (again.skipped, again.ran, again.interrupted) == (1, len(plan()) - 1, False)


def test_ctrl_c_between_two_scenes_keeps_the_first_and_says_so(monkeypatch):
    real = transfer_run.run_sweep
    calls = []

    def ctrl_c_before_the_second(*args, **kwargs):
        calls.append(1)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    monkeypatch.setattr(transfer_run, "run_sweep", ctrl_c_before_the_second)
    result = run_transfer_plan(plan(), SCENES, RunOptions(executor=InlineExecutor()))
    assert result.interrupted and not result.terminated
    assert [s.ran for s in result.sweeps] == [len(plan().sweeps[0]), 0]


def test_progress_covers_the_whole_report_once():
    class Seen:
        def __init__(self) -> None:
            self.starts: list[tuple[int, int]] = []
            self.advanced = 0

        def start(self, total: int, done: int = 0) -> None:
            self.starts.append((total, done))

        def advance(self, n: int) -> None:
            self.advanced += n

        def close(self) -> None:
            pass

    seen = Seen()
    whole = plan()
    run_transfer_plan(whole, SCENES, RunOptions(executor=InlineExecutor(), progress=seen))
    assert seen.starts == [(len(whole), 0)]
    assert seen.advanced == len(whole) == 2 * 3  # two scenes: design, noise ×2 and ×3
