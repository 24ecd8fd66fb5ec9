"""Small real sweeps: same rows on every executor, resuming, Ctrl-C, grading, the CLI."""

from __future__ import annotations

import json
import multiprocessing.connection
import sys
import time
from pathlib import Path

import pytest
from sweep_helpers import (
    DURATION,
    CountingExecutor,
    StopAfterFirstEpisode,
    new_children,
    wait_until,
)

from puckboard.sweep import (
    DaskExecutor,
    InlineExecutor,
    LocalExecutor,
    SweepPlan,
    open_store,
    run_sweep,
)
from puckboard.sweep.options import RunOptions

# Timing columns legitimately differ between runs; everything else must not.
TIMING = {"wall_s", "realtime_factor"}


def outcome_table(rows):
    return {r["key"]: {k: v for k, v in r.items() if k not in TIMING} for r in rows}


def small_plan(scene, seeds="0:2"):
    return SweepPlan.from_specs(
        scene.name,
        controllers=["stock", "improved"],
        seeds=seeds,
        sets=["noise.wheel_speed=0,0.2"],
        fixed={"duration": DURATION},
    )


@pytest.fixture(scope="module")
def inline_rows(short_scene):
    result = run_sweep(small_plan(short_scene), short_scene, RunOptions(executor=InlineExecutor()))
    assert not result.errors, result.errors[:1]
    return result.rows


def test_plan_runs_every_episode_once_with_real_outcomes(inline_rows, short_scene):
    plan = small_plan(short_scene)
    assert sorted(r["key"] for r in inline_rows) == sorted(
        s.key(plan.scenario) for s in plan.episodes()
    )
    assert all(r["sim_time_s"] > 0 and r["steps"] > 0 for r in inline_rows)
    # noise makes seeds differ, so equality between executors below is not vacuous
    noisy = [r["distance_m"] for r in inline_rows if r["param.noise.wheel_speed"] == 0.2]
    assert len(set(noisy)) > 1


def test_rows_do_not_depend_on_the_order_episodes_run_in(inline_rows, short_scene):
    """run_sweep runs the longest first, group by group; plan order, or any, is the same."""
    from puckboard.sweep.worker import run_batch

    plan = small_plan(short_scene)
    backwards = run_batch(short_scene, plan.scenario, list(plan.episodes())[::-1])
    assert outcome_table(backwards) == outcome_table(inline_rows)


@pytest.mark.slow
def test_local_processes_give_the_same_rows(inline_rows, short_scene):
    with LocalExecutor(workers=2) as executor:
        result = run_sweep(
            small_plan(short_scene), short_scene, RunOptions(executor=executor, batch_size=2)
        )
    assert result.ran == len(inline_rows)
    assert outcome_table(result.rows) == outcome_table(inline_rows)


@pytest.mark.slow
def test_dask_cluster_gives_the_same_rows(short_scene, tmp_path):
    """Through a scheduler address, as --scheduler does: controller files are uploaded."""
    distributed = pytest.importorskip("dask.distributed")
    controller_file = tmp_path / "student_one.py"
    controller_file.write_text(
        "from puckboard.behaviours import stock\n"
        "def make_controller(**params):\n    return stock(**params)\n"
    )
    plan = SweepPlan.from_specs(
        short_scene.name,
        controllers=["improved", f"{controller_file.as_posix()}:make_controller"],
        seeds="0:2",
        sets=["noise.wheel_speed=0,0.2"],
        fixed={"duration": DURATION},
    )
    expected = run_sweep(plan, short_scene, RunOptions(executor=InlineExecutor()))
    assert not expected.errors
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        with DaskExecutor(cluster.scheduler_address) as executor:
            assert executor.workers == 2
            result = run_sweep(plan, short_scene, RunOptions(executor=executor, batch_size=3))
        assert executor.client is None  # our client is closed; the cluster is the test's
    assert result.ran == len(plan)
    assert not result.errors, result.errors[:1]
    assert outcome_table(result.rows) == outcome_table(expected.rows)


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_resuming_runs_only_the_missing_episodes(tmp_path, short_scene, suffix):
    if suffix == ".parquet":
        pytest.importorskip("pyarrow")
    out = tmp_path / f"runs{suffix}"
    first = CountingExecutor()
    with open_store(out) as store:
        r1 = run_sweep(
            small_plan(short_scene, "0:1"), short_scene, RunOptions(executor=first, store=store)
        )
    assert len(first.ran) == r1.ran == 4

    second = CountingExecutor()
    with open_store(out) as store:
        r2 = run_sweep(
            small_plan(short_scene, "0:2"), short_scene, RunOptions(executor=second, store=store)
        )
    assert len(second.ran) == r2.ran == 4
    assert {s.seed for s in second.ran} == {1}
    assert r2.skipped == 4
    assert len(r2.outcomes) == 8  # the summary covers old and new episodes
    assert sum(g["episodes"] for g in r2.to_dict()["groups"]) == 8

    third = CountingExecutor()
    with open_store(out) as store:
        r3 = run_sweep(
            small_plan(short_scene, "0:2"), short_scene, RunOptions(executor=third, store=store)
        )
        assert len(store.rows()) == 8
    assert third.ran == [] and r3.ran == 0 and r3.skipped == 8


def test_ctrl_c_keeps_finished_rows_and_the_rerun_completes(tmp_path, short_scene):
    out = tmp_path / "runs.csv"
    plan = small_plan(short_scene, "0:2")
    interrupted = CountingExecutor(interrupt_after=1)
    with open_store(out) as store:
        result = run_sweep(
            plan, short_scene, RunOptions(executor=interrupted, store=store, batch_size=3)
        )
    assert result.interrupted
    assert result.ran == 3 == len(open_store(out).rows())

    rest = CountingExecutor()
    with open_store(out) as store:
        again = run_sweep(plan, short_scene, RunOptions(executor=rest, store=store, batch_size=3))
    assert not again.interrupted
    assert again.ran == len(rest.ran) == len(plan) - 3
    assert len(open_store(out).rows()) == len(plan)


@pytest.mark.slow
def test_cancelling_a_local_pool_stops_running_workers():
    executor = LocalExecutor(workers=2)
    before = set(multiprocessing.active_children())
    try:
        results = executor.run(time.sleep, [(0.0,), (60.0,), (60.0,), (60.0,)])
        assert next(results) is None
        processes = new_children(before)
        assert processes
        results.close()  # what Ctrl-C in the consuming loop does
        assert executor._hosts == []
        # every worker has exited: a process's sentinel is ready once it has ended
        sentinels = [p.sentinel for p in processes]
        assert sorted(multiprocessing.connection.wait(sentinels, timeout=0)) == sorted(sentinels)
    finally:
        executor.close()


def test_stopping_a_local_pool_keeps_what_its_running_batches_finished(short_scene, tmp_path):
    """After Ctrl-C the running batches end after their current episode and hand back
    the rows they have: nothing that finished is lost, then the workers are ended.

    Each batch says when it has finished its first episode and then waits for the stop
    (StopAfterFirstEpisode), so the pool is stopped while both surely run, however
    loaded the machine is."""
    import logging

    from puckboard.sweep.worker import run_batch

    plan = SweepPlan.from_specs(
        short_scene.name, controllers=["stock"], seeds="0:8", fixed={"duration": DURATION}
    )
    specs = list(plan.episodes())
    batches = [specs[:4], specs[4:]]
    markers = [tmp_path / "first", tmp_path / "second"]
    before = set(multiprocessing.active_children())
    with LocalExecutor(workers=2) as executor:
        task = (short_scene, plan.scenario, specs[:1], None, logging.ERROR, None)
        assert len(list(executor.run(run_batch, [task, task]))) == 2  # workers started
        processes = new_children(before)
        assert len(processes) == 2
        results = executor.run(
            run_batch,
            [(*task[:2], batch, *task[3:], StopAfterFirstEpisode(executor.stop_flag(), marker))
             for batch, marker in zip(batches, markers)],
        )  # fmt: skip
        wait_until(lambda: all(m.exists() for m in markers), "both batches' first episode")
        late = list(executor.stop(grace=60.0))
        results.close()
        assert executor._hosts == []
        sentinels = [p.sentinel for p in processes]
        assert sorted(multiprocessing.connection.wait(sentinels, timeout=0)) == sorted(sentinels)
    assert len(late) == 2
    for rows, batch in zip(sorted(late, key=lambda rows: rows[0]["seed"]), batches):
        # each stopped batch returns the episode it finished, and no more
        assert len(rows) == 1
        assert [r["key"] for r in rows] == [batch[0].key(plan.scenario)]


def test_grading_a_folder_ranks_and_scores_broken_submissions(tmp_path, short_scene):
    from puckboard.sweep import controllers_in_dir

    folder = tmp_path / "class"
    folder.mkdir()
    (folder / "alice.py").write_text(
        "from puckboard.behaviours import improved\n"
        "def make_controller(**params):\n    return improved(**params)\n"
    )
    (folder / "bob.py").write_text(
        "def make_controller(**params):\n    raise RuntimeError('oops')\n"
    )
    (folder / "carl.py").write_text("import sys\ndef make_controller(**params):\n    sys.exit(3)\n")
    (folder / "_helpers.py").write_text("X = 1\n")
    specs = controllers_in_dir(folder)
    assert [Path(s.split(":")[0]).name for s in specs] == ["alice.py", "bob.py", "carl.py"]
    plan = SweepPlan.from_specs(
        short_scene.name, controllers=specs, seeds="0:2", fixed={"duration": DURATION}
    )
    result = run_sweep(plan, short_scene, RunOptions(executor=InlineExecutor()))
    ranking = result.ranking()
    assert ranking[0].controller.endswith("alice.py:make_controller")
    for broken in ranking[1:]:
        assert broken.failures == {"error": 2} and broken.successes == 0
    assert len(result.errors) == 4
    assert any("oops" in e for e in result.errors)
    assert any("SystemExit" in e for e in result.errors)


def test_cli_json_summary(tmp_path, capsys):
    from puckboard.cli import main

    out = tmp_path / "runs.csv"
    plot = tmp_path / "rate.png"
    argv = [
        "sweep", "line-follow", "--controller", "stock", "--seeds", "0:2",
        "--set", "noise.proximity=0,0.1", "--duration", "3", "--workers", "1",
        "--out", str(out), "--json", "--quiet", "--plot", str(plot),
    ]  # fmt: skip
    assert main(argv) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["episodes"] == 4 and summary["ran"] == 4
    assert len(summary["groups"]) == 2
    for group in summary["groups"]:
        assert set(group) >= {
            "controller", "params", "episodes", "successes", "success_rate",
            "ci95_low", "ci95_high", "failures",
        }  # fmt: skip
        assert group["controller"] == "stock" and group["episodes"] == 2
        assert group["ci95_low"] <= group["success_rate"] <= group["ci95_high"]
        assert sum(group["failures"].values()) == 2 - group["successes"]
    assert plot.stat().st_size > 0
    assert main(argv) == 0  # resumed: nothing left to run
    assert json.loads(capsys.readouterr().out)["ran"] == 0


CRUISE_ONLY = (
    "from puckboard.behaviours import Controller, Cruise\n"
    "def make_controller(**params):\n"
    "    return Controller([Cruise()], name='cruise')\n"
)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--seeds", "3"], "expected A:B"),
        (["--set", "noise.prox=1"], "unknown parameter"),
        (["--set", "layer.Nope.gain=1"], "has a layer named 'Nope'"),
        (["--out", "runs.txt"], ".csv or .parquet"),
        (["--plot", "x.png"], "--plot needs a parameter swept"),
        (["--workers", "0"], "at least 1"),
        # what 'run' refuses at once, refused before the first episode
        (["--controller", "improvd"], "controller 'improvd' cannot be built: unknown controller"),
        (["--controller", "stock", "--controller", "no_such_module:make"], "'no_such_module'"),
        (["--set", "layer.LineFollow.inner_factor=0.3,abc"],
         "needs a number (the parameter is float), got 'abc'"),
        (["--set", "dt=0.05,1e-9"], "more than one episode may take"),
        (["--controller", "improved", "--controller", "CRUISE", "--set",
          "layer.LineFollow.inner_factor=0.3"], "no controller has a layer 'LineFollow'"),
    ],
)  # fmt: skip
def test_cli_rejects_bad_input_with_a_clear_message(args, message, capsys, tmp_path):
    from puckboard.cli import main

    cruise = tmp_path / "cruise.py"
    cruise.write_text(CRUISE_ONLY)
    args = [a.replace("CRUISE", f"{cruise.as_posix()}:make_controller") for a in args]
    out = tmp_path / "runs.csv"
    extra = [] if "--out" in args else ["--out", str(out)]
    workers = [] if "--workers" in args else ["--workers", "1"]  # an option is given once
    assert main(["sweep", "line-follow", *workers, "--quiet", *extra, *args]) == 2
    captured = capsys.readouterr()
    assert message in captured.err
    assert len(captured.err.splitlines()) == 1, captured.err
    assert captured.out == "" and not out.exists()  # nothing ran


def test_cli_grades_a_folder_with_a_broken_submission_as_error_episodes(tmp_path, capsys):
    """Submissions are the exception: one that does not build must not stop the class."""
    from puckboard.cli import main

    folder = tmp_path / "class"
    folder.mkdir()
    (folder / "alice.py").write_text(CRUISE_ONLY)
    (folder / "bob.py").write_text(
        "def make_controller(**params):\n    raise RuntimeError('oops')\n"
    )
    argv = [
        "sweep", "line-follow", "--controllers-dir", str(folder), "--seeds", "0:1",
        "--duration", "1", "--workers", "1", "--quiet", "--json",
    ]  # fmt: skip
    assert main(argv) == 0
    captured = capsys.readouterr()
    assert "bob.py:make_controller' cannot be built: oops" in captured.err
    groups = {Path(g["controller"]).name: g for g in json.loads(captured.out)["groups"]}
    assert groups["bob.py:make_controller"]["failures"] == {"error": 1}
    assert "error" not in groups["alice.py:make_controller"]["failures"]


@pytest.mark.slow
def test_a_dying_worker_process_is_reported_not_hung():
    import os

    from puckboard.sweep import WorkerLostError

    with LocalExecutor(workers=1) as executor, pytest.raises(WorkerLostError, match="died"):
        list(executor.run(os._exit, [(3,)]))


@pytest.mark.skipif(
    sys.gettrace() is not None,
    reason=(
        "a tracer is active (coverage, a debugger): the watchdog's exception stops the "
        "episode, but on Python 3.11 it can land inside the tracer, and coverage then hangs "
        "(coveragepy issue 1626); puckboard/sweep/watchdog.py says so"
    ),
)
def test_a_controller_that_never_returns_is_stopped_by_the_episode_timeout(tmp_path, short_scene):
    spinning = tmp_path / "spinning.py"
    spinning.write_text(
        "from puckboard.behaviours import Controller, Cruise\n"
        "class Spin(Cruise):\n"
        "    def command(self, frame):\n"
        "        while True:\n"
        "            pass\n"
        "def make_controller(**params):\n"
        "    return Controller([Spin()], name='spin')\n"
    )
    plan = SweepPlan.from_specs(
        short_scene.name,
        controllers=[f"{spinning.as_posix()}:make_controller", "improved"],
        seeds="0:2",
        fixed={"duration": DURATION},
    )
    result = run_sweep(
        plan, short_scene, RunOptions(executor=InlineExecutor(), episode_timeout=1.0)
    )
    by_controller = {g.controller: g for g in result.ranking()}
    assert by_controller[plan.controllers[0]].failures == {"error": 2}
    assert len(result.errors) == 2
    assert all("wall-clock limit of 1 s" in e for e in result.errors)
    # the good controller's episodes ran normally after the runaway ones were stopped
    assert by_controller["improved"].failures.get("error") is None


def test_a_batch_asks_its_stop_flag_before_each_episode(short_scene):
    from puckboard.sweep.worker import run_batch

    specs = list(small_plan(short_scene).episodes())[:5]
    asked = []

    def stop_after_two():
        asked.append(True)
        return len(asked) > 2

    rows = run_batch(short_scene, short_scene.name, specs, stop=stop_after_two)
    assert [r["key"] for r in rows] == [s.key(short_scene.name) for s in specs[:2]]
    assert len(asked) == 3


@pytest.mark.slow
def test_a_stopped_dask_sweep_frees_its_workers_after_one_episode(short_scene):
    """Dask cannot interrupt a running task; the batch sees the stop flag instead."""
    pytest.importorskip("dask.distributed")
    import logging

    from distributed import Event

    from puckboard.sweep.progress import NullProgress
    from puckboard.sweep.worker import run_batch

    specs = list(small_plan(short_scene).episodes())[:6]
    with DaskExecutor(local_workers=1) as executor:
        # the flag works on a worker: unset, the whole batch runs
        unset = executor.client.submit(
            run_batch, short_scene, short_scene.name, specs[:2], None, logging.ERROR, None,
            executor.stop_flag(), pure=False,
        )  # fmt: skip
        assert len(unset.result(timeout=120)) == 2

        # Ctrl-C during a sweep (here: raised by the progress display) sets the flag the
        # running batches were given, and the next sweep gets a fresh one
        class InterruptingProgress(NullProgress):
            def advance(self, n: int) -> None:
                raise KeyboardInterrupt

        given = executor.stop_flag()
        result = run_sweep(
            small_plan(short_scene),
            short_scene,
            RunOptions(executor=executor, batch_size=1, progress=InterruptingProgress()),
        )
        assert result.interrupted and 1 <= result.ran < len(small_plan(short_scene))
        assert Event(given.name, client=executor.client).is_set()
        assert executor.stop_flag().name != given.name
        assert not executor.stop_flag()()

        # set while the batch is queued or on its first episode: at most one more runs
        flag = executor.stop_flag()
        stopped = executor.client.submit(
            run_batch, short_scene, short_scene.name, specs, None, logging.ERROR, None, flag,
            pure=False,
        )  # fmt: skip
        Event(flag.name, client=executor.client).set()
        assert len(stopped.result(timeout=120)) <= 1
