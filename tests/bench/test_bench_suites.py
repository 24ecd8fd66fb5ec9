"""``puckboard bench``: suites resolve by name, missing ones are skipped, output parses."""

from __future__ import annotations

import json

import pytest

from puckboard import bench
from puckboard.bench import report
from puckboard.cli import main


def test_list_names_every_registered_suite(capsys):
    assert main(["bench", "--list"]) == 0
    out = capsys.readouterr().out
    for name in ("core", "sim", "coppeliasim", "sweep", "estimation", "emulator", "sensitivity"):
        assert name in out


def test_unknown_suite_is_a_one_line_error(capsys):
    assert main(["bench", "--suite", "nope"]) == 2
    err = capsys.readouterr().err
    assert "unknown suite 'nope'" in err and len(err.strip().splitlines()) == 1


def test_a_suite_whose_module_is_missing_is_skipped_with_a_note(monkeypatch):
    monkeypatch.setitem(bench.SUITES, "ghost", "puckboard.no_such_module:run_suite")
    result = bench.run_suites(["ghost"])
    assert "skipped" in result["suites"]["ghost"]
    assert "no_such_module" in result["suites"]["ghost"]["skipped"]


def test_core_suite_json_has_both_sides_of_each_comparison(capsys):
    assert main(["bench", "--suite", "core", "--steps", "50", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    core = data["suites"]["core"]
    for key in (
        "blackboard_put_get_us",
        "py_trees_client_set_get_us",
        "arbiter_tick_us",
        "py_trees_selector_tick_us",
        "arbiter_tick_traced_us",
        "observe_pass_us",
    ):
        assert core[key] > 0
    assert core["arbiter_layers"] == 4
    # the figure to quote is the ratio of one run, whatever the machine's speed
    ratio = core["arbiter_tick_us"] / core["py_trees_selector_tick_us"]
    assert core["arbiter_over_selector"] == round(ratio, 2)
    assert core["tracing_adds_us"] == core["arbiter_tick_traced_us"] - core["arbiter_tick_us"]
    assert data["machine"]["cpus"] >= 1


@pytest.mark.slow
def test_sim_suite_reports_rate_split_and_camera():
    from puckboard.bench.sim import run_suite

    res = run_suite(10)
    assert res["steps_per_s"] > 0
    assert res["realtime_factor"] == pytest.approx(res["steps_per_s"] * res["dt_s"])
    assert len(res["cost_us_per_step"]) == 4
    assert len(res["cpu_us_per_step"]) == 3
    assert res["camera_us_per_frame"] > 0
    text = report.format_results({"machine": bench.machine(), "suites": {"sim": res}})
    assert "steps_per_s" in text and "camera_us_per_frame" in text


def test_floor_suite_sets_the_full_stack_beside_its_floor_in_one_run(monkeypatch):
    from puckboard.bench import floor

    monkeypatch.setattr(floor, "REPEATS", 1)
    res = floor.run_suite(5)
    for name in floor.CONTROLLERS:
        r = res[name]
        # the engine replays the very trajectory the full stack drove
        assert r["engine_replay_identical"] is True
        for clock in ("us", "cpu_us"):
            floor_us = r[f"engine_step_{clock}"] + 2 * r[f"bare_tick_{clock}"]
            assert r[f"floor_{clock}"] == floor_us > 0
        assert r["ratio"] == round(r["full_stack_us"] / r["floor_us"], 2)
        assert r["ratio_cpu"] == round(r["full_stack_cpu_us"] / r["floor_cpu_us"], 2)
        assert set(r["split_cpu_us"]) == {"sensing", "ticks", "commands", "engine", "judge"}
    text = report.format_results({"machine": bench.machine(), "suites": {"floor": res}})
    assert "ratio_cpu" in text and "robust:" in text


def test_table_shows_records_one_block_each_and_cuts_long_lists():
    rows = [
        {"seed": k, "errors": {"final_m": 0.001 * k}} for k in range(report.TABLE_LIST_LIMIT + 3)
    ]
    text = report.format_results({"machine": {}, "suites": {"demo": {"rows": rows}}})
    assert f"rows: {len(rows)} records" in text
    assert "final_m" in text and "{" not in text
    assert "3 more (see --json)" in text


def test_suite_options_reach_only_the_suites_that_take_them(monkeypatch):
    seen = {}

    def takes_seeds(steps, *, seeds=(0,)):
        seen["seeds"] = seeds
        return {"n": len(seeds)}

    def takes_nothing(steps):
        return {"steps": steps}

    monkeypatch.setitem(bench.SUITES, "a", f"{__name__}:_suite_a")
    monkeypatch.setitem(bench.SUITES, "b", f"{__name__}:_suite_b")
    monkeypatch.setitem(globals(), "_suite_a", takes_seeds)
    monkeypatch.setitem(globals(), "_suite_b", takes_nothing)
    result = bench.run_suites(["a", "b"], steps=3, options={"seeds": [4, 5]})
    assert seen["seeds"] == [4, 5]
    assert result["suites"] == {"a": {"n": 2}, "b": {"steps": 3}}


def test_an_option_no_selected_suite_takes_is_a_clear_error(capsys):
    assert main(["bench", "--suite", "core", "--seeds", "1"]) == 2
    err = capsys.readouterr().err
    assert "--seeds is an option of suite estimation" in err and "--suite estimation" in err


def test_a_bad_suite_option_value_is_reported_not_raised(capsys):
    assert main(["bench", "--suite", "estimation", "--gyro-noise", "5", "--steps", "1"]) == 2
    assert "gyro_noise must lie in [0.0, 1.0], got 5.0" in capsys.readouterr().err


def test_timing_helper_takes_the_median_of_repeats(monkeypatch):
    from puckboard.bench import timing

    clock = iter([0.0, 1.0, 0.0, 5.0, 0.0, 2.0])  # three repeats of one call: 1 s, 5 s, 2 s
    monkeypatch.setattr(timing.time, "perf_counter", lambda: next(clock))
    assert timing.seconds_per_call(lambda: None, 1, repeats=3) == 2.0
    with pytest.raises(ValueError, match="calls and repeats must be at least 1"):
        timing.seconds_per_call(lambda: None, 0)
    with pytest.raises(ValueError, match="no timing samples"):
        timing.median_seconds([])


def test_swarm_grid_places_robots_apart_and_clear_of_walls_and_obstacles():
    import math

    from puckboard.bench.scale import CLEARANCE, GRID, ROBOT_COUNTS, grid_robots, swarm_with
    from puckboard.scenario import load_scene
    from puckboard.sim.world import World

    shipped = load_scene("swarm")
    assert len(shipped.robots) == 30 and {r.profile for r in shipped.robots} == {"epuck"}
    for n in ROBOT_COUNTS:
        robots = grid_robots(shipped, n)
        assert len(robots) == n
        for a in robots:
            assert shipped.arena.xmin + CLEARANCE - 1e-9 <= a.x <= shipped.arena.xmax - CLEARANCE
            for b in robots:
                if a is not b:
                    assert math.hypot(a.x - b.x, a.y - b.y) >= GRID - 1e-9
        world = World(swarm_with(n), seed=0)
        assert not world.contacts_now.any()  # nobody starts touching anything
    with pytest.raises(ValueError, match="holds at most"):
        grid_robots(shipped, 10_000)


def test_scale_suite_reports_every_robot_count():
    result = bench.run_suites(["scale"], steps=2)["suites"]["scale"]
    rows = result["by_robot_count"]
    assert list(rows) == ["2 robots", "10 robots", "30 robots", "50 robots"]
    for row in rows.values():
        assert row["steps_per_s"] > 0 and row["us_per_robot_step"] > 0


def test_web_suite_measures_with_and_without_stream_clients():
    pytest.importorskip("aiohttp")
    from puckboard.bench.web import run_suite

    out = run_suite(steps=60, clients=3)
    assert out["with_clients"]["connected"] == 3
    assert out["without_clients"]["frames_per_s_per_client"] is None
    assert out["with_clients"]["frames_per_s_per_client"] > 0  # every stream got frames
    for key in ("without_web_view", "without_clients", "with_clients"):
        assert out[key]["realtime_factor"] > 0


def test_when_every_suite_asked_for_is_skipped_nothing_was_measured(monkeypatch, capsys):
    monkeypatch.setitem(bench.SUITES, "ghost", "puckboard.no_such_module:run_suite")
    assert main(["bench", "--suite", "ghost", "--json"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    (line,) = captured.err.strip().splitlines()
    assert line.startswith("puckboard bench: error: nothing was measured: module not available")
    assert "no_such_module" in line


def test_a_skipped_suite_next_to_one_that_ran_is_a_note(monkeypatch, capsys):
    monkeypatch.setitem(bench.SUITES, "ghost", "puckboard.no_such_module:run_suite")
    assert main(["bench", "--suite", "ghost", "--suite", "core", "--steps", "5", "--json"]) == 0
    suites = json.loads(capsys.readouterr().out)["suites"]
    assert "skipped" in suites["ghost"] and "arbiter_tick_us" in suites["core"]
