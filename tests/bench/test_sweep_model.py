"""The scheduling model of ``puckboard bench --suite sweep``: its arithmetic, by hand."""

from __future__ import annotations

import json
import random

import pytest

from puckboard.bench.sweep_model import episodes_from_rows, makespan, model_sweep, old_batches
from puckboard.sweep.plan import SweepPlan


def test_list_scheduling_gives_each_task_to_the_first_free_worker():
    # 3 -> w1, 3 -> w2, 2 -> w1 (5), 2 -> w2 (5), 2 -> w1 (7)
    assert makespan([3, 3, 2, 2, 2], 2) == 7
    # the long task last: w1 and w2 take two short ones each, then w1 takes the long one
    assert makespan([1, 1, 1, 1, 4], 2) == 6
    assert makespan([4, 1, 1, 1, 1], 2) == 4  # longest first: w2 runs the short ones
    assert makespan([1.0] * 10, 1) == 10
    assert makespan([5.0], 16) == 5


def two_groups(short: float, long: float, seeds: int = 96):
    """A plan of two parameter groups, the second one's episodes all longer: as the
    improved controller on the physical robot's profile (fails early) and V-REP's
    (succeeds, so runs to the end)."""
    plan = SweepPlan.from_specs(
        "two-robot-pass", controllers=["improved"], seeds=f"0:{seeds}",
        sets=["robot.profile=epuck,epuck-vrep"],
    )  # fmt: skip
    rng = random.Random(1)
    return [
        (s, (short if s.param_dict["robot.profile"] == "epuck" else long) * rng.uniform(0.8, 1.2))
        for s in plan.episodes()
    ]


def test_old_batches_were_equal_slices_of_the_plan():
    specs = [s for s, _ in two_groups(1, 1)]
    batches = old_batches(specs, 16)
    assert len(batches) == 64 and {len(b) for b in batches} == {3}
    assert [s for b in batches for s in b] == specs


def test_the_model_charges_start_up_and_overheads_and_compares_both_batchings():
    episodes = two_groups(0.28, 0.45)
    work = sum(d for _, d in episodes)
    model = model_sweep(episodes, startup_s=0.0, workers=(1, 16))
    one, sixteen = model["workers"][1], model["workers"][16]
    assert one["time_before_s"] == pytest.approx(work)  # one worker: all of it, in turn
    assert one["efficiency_before"] == one["efficiency_after"] == pytest.approx(1.0)
    assert sixteen["tasks_before"] == 64
    assert sixteen["ideal_s"] == pytest.approx(work / 16)
    # plan order leaves the long group for the end, in batches of 3: workers wait
    assert sixteen["time_before_s"] > 1.05 * sixteen["ideal_s"]
    assert sixteen["time_after_s"] < sixteen["time_before_s"]
    assert sixteen["efficiency_after"] > sixteen["efficiency_before"]
    # start-up and per-episode and per-task costs add up as stated
    slow = model_sweep(
        episodes, startup_s={1: 1.0, 16: 2.0}, per_episode_s=0.01, per_task_s=0.5,
        workers=(1, 16),
    )["workers"]  # fmt: skip
    assert slow[1]["time_before_s"] == pytest.approx(1.0 + work + 0.01 * 192 + 0.5 * 24)
    assert slow[16]["time_after_s"] > sixteen["time_after_s"] + 2.0


def test_plan_order_is_rebuilt_from_the_rows_of_an_out_file():
    episodes = two_groups(1, 2, seeds=4)
    rows = [
        {"controller": s.controller, "seed": str(s.seed), "wall_s": str(d),
         "params": json.dumps({"robot.profile": s.param_dict["robot.profile"]})}
        for s, d in episodes
    ]  # fmt: skip
    shuffled = rows[:1] + random.Random(2).sample(rows[1:], len(rows) - 1)
    rebuilt = episodes_from_rows(shuffled)
    assert [s for s, _ in rebuilt] == [s for s, _ in episodes]
    assert [d for _, d in rebuilt] == pytest.approx([d for _, d in episodes])


@pytest.mark.slow
def test_the_suite_measures_the_overheads_and_models_an_out_file(tmp_path, capsys):
    from puckboard.cli import main

    out = tmp_path / "runs.csv"
    sweep = [
        "sweep",
        "line-follow",
        "--controller",
        "stock",
        "--seeds",
        "0:6",
        "--duration",
        "2",
        "--set",
        "noise.ground=0,0.1",
        "--workers",
        "1",
        "--quiet",
        "--out",
        str(out),
    ]
    assert main(sweep) == 0
    capsys.readouterr()
    assert main(["bench", "--suite", "sweep", "--steps", "5", "--durations", str(out),
                 "--json"]) == 0  # fmt: skip
    suite = json.loads(capsys.readouterr().out)["suites"]["sweep"]
    overheads = suite["overheads"]
    assert len(overheads["worker_ready_s"]["local_2"]) == 2
    assert all(t > 0 for t in overheads["worker_ready_s"]["local_2"])
    assert overheads["task_round_trip_ms"] > 0 and overheads["collect_ms_per_row"] > 0
    model = suite["model"]
    assert model["episodes"] == 12 and model["durations_from"] == str(out)
    assert set(model["workers"]) == {"1", "2", "4", "8", "16"}
    for figures in model["workers"].values():
        assert 0 < figures["efficiency_after"] <= 1.0 + 1e-9


def test_the_suite_refuses_a_file_that_is_not_a_sweep_output(tmp_path, capsys):
    from puckboard.cli import main

    bad = tmp_path / "notes.csv"
    bad.write_text("a,b\n1,2\n")
    assert main(["bench", "--suite", "sweep", "--durations", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "is not a sweep's --out file" in err and len(err.strip().splitlines()) == 2
