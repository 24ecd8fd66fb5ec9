"""Sensitivity analyses: their points, what they run, how they are summarised and shown."""

from __future__ import annotations

import dataclasses
import itertools
import json
import math
import struct

import pytest
from sweep_helpers import DURATION, CountingExecutor

from puckboard.control.episode import run_episode
from puckboard.profile import get_profile, load_profile_file, uncertainty
from puckboard.profile.setting_names import setting_value
from puckboard.sensitivity import (
    SensitivityResult,
    analyse,
    field_values,
    format_result,
    plot_sensitivity,
    run_sensitivity,
    sensitivity_plan,
)
from puckboard.sensitivity.one_at_a_time.plan import PLAUSIBLE, SHIPPED, VALUE
from puckboard.sweep import InlineExecutor, PlanError, SweepPlan, open_store
from puckboard.sweep.options import RunOptions
from puckboard.sweep.plan import params_key
from puckboard.sweep.rows import Outcome
from puckboard.sweep.run import SweepResult


# -- values and points ---------------------------------------------------------------------
def test_values_are_evenly_spaced_with_both_ends_of_the_range():
    values = field_values(0.030, 0.033, 7)
    assert values[0] == 0.030 and values[-1] == 0.033 and len(values) == 7
    steps = [b - a for a, b in itertools.pairwise(values)]
    assert max(steps) - min(steps) < 1e-15
    assert field_values(0.7, 1.3, 1) == (1.0,)
    assert field_values(0.035, 0.035, 7) == (0.035,)
    with pytest.raises(PlanError, match="--values must be at least 1"):
        field_values(0.0, 1.0, 0)


def plan_for(profiles=("epuck",), **kwargs):
    kwargs.setdefault("controllers", ["improved"])
    kwargs.setdefault("seeds", range(3))
    return sensitivity_plan("two-robot-pass", profiles=list(profiles), **kwargs)


def test_every_uncertain_field_of_each_profile_is_varied_on_its_range():
    plan = plan_for(("epuck", "epuck-vrep"))
    for name in ("epuck", "epuck-vrep"):
        ranges = uncertainty(get_profile(name))
        fields = [f for f in plan.fields if f.profile == name]
        assert [f.path for f in fields] == list(ranges)
        for f in fields:
            assert (f.low, f.high) == (ranges[f.path].low, ranges[f.path].high)
            assert f.values == field_values(f.low, f.high, 7)
            assert f.shipped == setting_value(get_profile(name), f.path)


def test_each_point_sets_one_field_on_top_of_its_profile():
    plan = plan_for(("epuck", "epuck-vrep"))
    for point in plan.points:
        base = {"robot.profile": point.profile}
        if point.kind == SHIPPED:
            assert point.params == base
        elif point.kind == PLAUSIBLE:
            assert point.params == {**base, "variation": "plausible"}
        else:
            assert point.kind == VALUE
            assert point.params == {**base, f"profile.{point.field}": point.value}
    kinds = [(p.profile, p.kind) for p in plan.points]
    for name in ("epuck", "epuck-vrep"):
        assert kinds.count((name, SHIPPED)) == kinds.count((name, PLAUSIBLE)) == 1
    # the sweep runs exactly these points, each on every seed (common random numbers)
    keys = [plan.point_key(p) for p in plan.points]
    assert [params_key(c) for c in plan.sweep.combinations()] == keys
    seeds = {}
    for spec in plan.sweep.episodes():
        seeds.setdefault(params_key(spec.param_dict), []).append(spec.seed)
    assert all(s == [0, 1, 2] for s in seeds.values()) and len(seeds) == len(plan.points)


def test_a_value_that_builds_the_shipped_robot_is_the_shipped_point():
    """ir_gain's middle value is the shipped 1.0: its episodes would be the shipped ones."""
    plan = plan_for(fields=["ir_gain", "prox_radius.side"], values=3)
    gains = [p.value for p in plan.points if p.field == "ir_gain"]
    assert gains == [0.7, 1.3]
    sides = [p.value for p in plan.points if p.field == "prox_radius.side"]
    assert sides == [0.030, 0.0315, 0.033]  # 31 mm, shipped, is not among the values
    # the wheels: a wheel set to the nominal radius rolls as the nominal one does
    wheel = plan_for(fields=["wheel_radius.left"], values=2)
    assert [p.value for p in wheel.points if p.kind == VALUE] == [0.0200]


def test_with_variation_every_other_number_is_drawn_at_each_value():
    plan = plan_for(fields=["ir_gain"], values=3, variation="plausible")
    values = [p for p in plan.points if p.kind == VALUE]
    assert [p.value for p in values] == [0.7, 1.0, 1.3]  # 1.0 is no longer the shipped robot
    assert all(p.params["variation"] == "plausible" for p in values)
    assert [p.params for p in plan.points if p.kind == SHIPPED] == [{"robot.profile": "epuck"}]


def test_a_profile_file_s_own_numbers_are_measured_not_varied(repo_root):
    mine = load_profile_file(repo_root / "examples" / "my-epuck.toml")
    plan = plan_for((mine,))
    paths = [f.path for f in plan.fields]
    assert "prox_max_distance" not in paths  # the file sets it
    assert "wheel_radius.left" not in paths  # the file's wheel_radius sets both wheels
    assert "ir_gain" in paths  # the file sets only the right side sensor's gain
    for point in plan.points:
        assert point.profile == "my-epuck"
        for path, value in mine.overrides:
            assert point.params[f"profile.{path}"] == value
        assert point.params["robot.profile"] == "epuck"


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"fields": ["prox_radius.sides"]}, "did you mean prox_radius.side"),
        ({"fields": ["prox_radius.side"], "profiles": ("epuck-vrep",)}, "not an uncertain"),
        ({"values": 0}, "--values must be at least 1"),
        ({"profiles": ("epuck", "epuck")}, "profile listed twice"),
        ({"variation": "wild"}, "unknown variation 'wild'; use one of none, plausible"),
    ],
)
def test_bad_plans_are_one_line_saying_what_to_do(kwargs, message):
    profiles = kwargs.pop("profiles", ("epuck",))
    with pytest.raises(PlanError, match=message) as info:
        plan_for(profiles, **kwargs)
    assert "\n" not in str(info.value)


def test_sweep_points_are_crossed_with_the_grid_and_checked():
    plan = SweepPlan(
        "line-follow",
        seeds=range(2),
        grid={"noise.proximity": (0.0, 0.1)},
        fixed={"duration": 2.0},
        points=({"robot.profile": "epuck"}, {"robot.profile": "epuck-vrep"}),
    )
    assert plan.combinations() == [
        {"duration": 2.0, "robot.profile": p, "noise.proximity": n}
        for p in ("epuck", "epuck-vrep")
        for n in (0.0, 0.1)
    ]
    assert len(plan) == 8
    with pytest.raises(PlanError, match="listed twice"):
        SweepPlan("line-follow", points=({"dt": 0.05}, {"dt": 0.05}))
    with pytest.raises(PlanError, match="both in a point and swept or fixed"):
        SweepPlan("line-follow", fixed={"dt": 0.05}, points=({"dt": 0.07},))
    with pytest.raises(PlanError, match="unknown parameter"):
        SweepPlan("line-follow", points=({"noise.nope": 1.0},))


# -- summaries -------------------------------------------------------------------------------
def outcomes_for(plan, successes):
    """Outcomes of ``plan``: ``successes[point index]`` of each point's episodes succeed."""
    out = []
    for index, point in enumerate(plan.points):
        for seed in plan.sweep.seeds:
            won = seed < successes[index]
            out.append(
                Outcome(
                    key=f"{plan.point_key(point)}/{seed}", controller="improved",
                    params=tuple(sorted(point.params.items())), seed=seed, success=won,
                    failure="" if won else "lost_line", progress_laps=0.5, collisions=0.0,
                )
            )  # fmt: skip
    return out


def test_fields_are_ranked_by_the_spread_of_their_rate():
    plan = plan_for(fields=["prox_radius.side", "ir_gain"], values=3, seeds=range(20))
    index = {(p.field, p.value): i for i, p in enumerate(plan.points)}
    wins = [5] * len(plan.points)
    wins[index[("prox_radius.side", 0.030)]] = 19  # shipped 5 of 20: spread 70 %, clear
    wins[index[("ir_gain", 1.3)]] = 9  # spread 20 %: intervals overlap
    (analysis,) = analyse(plan, outcomes_for(plan, wins))
    assert [r.field.path for r in analysis.fields] == ["prox_radius.side", "ir_gain"]
    side, gain = analysis.fields
    assert math.isclose(side.spread, 0.70) and side.clear
    assert math.isclose(gain.spread, 0.20) and not gain.clear
    assert side.highest.value == 0.030 and side.lowest.stats.success_rate == 0.25
    # the shipped point sits on each curve at the shipped value, from the shipped episodes
    assert [(v.value, v.shipped) for v in side.values] == [
        (0.030, False), (0.031, True), (0.0315, False), (0.033, False)
    ]  # fmt: skip
    assert [(v.value, v.shipped) for v in gain.values] == [(0.7, False), (1.0, True), (1.3, False)]
    assert analysis.shipped.successes == analysis.plausible.successes == 5
    assert analysis.shipped.episodes == 20


def test_an_unfinished_point_is_left_out_of_its_curve():
    plan = plan_for(fields=["ir_gain"], values=3, seeds=range(4))
    outcomes = [o for o in outcomes_for(plan, [2] * len(plan.points)) if "1.3" not in o.key]
    (analysis,) = analyse(plan, outcomes)
    (gain,) = analysis.fields
    assert [v.value for v in gain.values] == [0.7, 1.0]


# -- real episodes -------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def short_analysis(short_scene):
    plan = sensitivity_plan(
        short_scene.name, profiles=["epuck"], controllers=["improved"], seeds=range(2),
        fields=["wheel_radius.left", "ir_gain"], values=3, fixed={"duration": DURATION},
    )  # fmt: skip
    return plan, run_sensitivity(plan, short_scene, RunOptions(executor=InlineExecutor()))


def test_each_value_is_the_run_that_set_profile_field_value_gives(short_analysis, short_scene):
    """Any point of the figure is repeatable as one run with --set profile.PATH=VALUE."""
    plan, result = short_analysis
    assert not result.sweep.errors and result.sweep.ran == len(plan)
    row = next(r for r in result.sweep.rows if r.get("param.profile.wheel_radius.left") == 0.020)
    again = run_episode(
        short_scene, controller="improved", seed=row["seed"], duration=DURATION,
        overrides={"robot.profile": "epuck", "profile.wheel_radius.left": 0.020},
    ).to_dict()  # fmt: skip
    assert (row["distance_m"], row["steps"]) == (
        sum(r["distance_m"] for r in again["robots"]),
        again["steps"],
    )
    assert json.loads(row["robot.epuck.profile_values"])["wheel_radius.left"] == 0.020
    # and the value changed the run: the same seed at the other end of the range differs
    other = next(
        r for r in result.sweep.rows
        if r.get("param.profile.wheel_radius.left") == 0.02025 and r["seed"] == row["seed"]
    )  # fmt: skip
    assert other["distance_m"] != row["distance_m"]


def test_a_stored_analysis_resumes_without_running_anything_again(short_scene, tmp_path):
    plan = sensitivity_plan(
        short_scene.name, profiles=["epuck"], controllers=["stock"], seeds=range(2),
        fields=["ir_gain"], values=2, fixed={"duration": DURATION},
    )  # fmt: skip
    with open_store(tmp_path / "runs.csv") as store:
        first = run_sensitivity(
            plan, short_scene, RunOptions(executor=InlineExecutor(), store=store)
        )
    counting = CountingExecutor()
    with open_store(tmp_path / "runs.csv") as store:
        again = run_sensitivity(plan, short_scene, RunOptions(executor=counting, store=store))
    assert counting.ran == [] and again.sweep.skipped == len(plan) == first.sweep.ran
    assert [a.to_dict() for a in again.analyses] == [a.to_dict() for a in first.analyses]


def test_ctrl_c_keeps_what_ran_and_summarises_it(short_scene):
    plan = sensitivity_plan(
        short_scene.name, profiles=["epuck"], controllers=["stock"], seeds=range(2),
        fields=["ir_gain"], values=2, fixed={"duration": DURATION},
    )  # fmt: skip
    result = run_sensitivity(
        plan, short_scene, RunOptions(executor=CountingExecutor(interrupt_after=1), batch_size=1)
    )
    assert result.sweep.interrupted and result.sweep.ran == 1
    (analysis,) = result.analyses
    values = [v.stats for v in analysis.fields[0].values if not v.shipped]
    ran = [analysis.shipped, analysis.plausible, *values]
    assert sum(g.episodes for g in ran if g is not None) == 1


# -- report and figure -----------------------------------------------------------------------
def synthetic_result(successes=None, seeds=range(10)):
    plan = plan_for(fields=["prox_radius.side", "ir_gain"], values=3, seeds=seeds)
    wins = successes or [i % 4 for i in range(len(plan.points))]
    outcomes = outcomes_for(plan, wins)
    sweep = SweepResult(plan=plan.sweep, outcomes=outcomes, ran=len(outcomes), wall_s=2.0)
    return SensitivityResult.of(plan, sweep)


def test_the_report_gives_every_value_its_rate_and_interval_in_readable_units():
    text = format_result(synthetic_result())
    assert text.splitlines()[0] == (
        "two-robot-pass: 70 of 70 episodes (70 run), 2.0 s, 35.0 episodes/s"
    )
    assert "improved on epuck (seeds 0:10)" in text
    lines = text.splitlines()
    start = lines.index(next(line for line in lines if line.startswith("prox_radius.side (mm)")))
    curve = lines[start : start + 6]
    assert [line.split()[0] for line in curve[2:]] == ["30", "31", "31.5", "33"]
    assert "(shipped)" in curve[3]
    # 31 mm is the shipped point: 0 of 10 (point 0), [0, 28] %
    assert curve[3].split()[2:8] == ["10", "0", "0", "%", "[0,", "28]"]
    assert "range: sources disagree: 30 mm: GCtronic" in lines[start + 6]


def test_the_json_has_every_value_s_rate_with_its_interval():
    data = synthetic_result().to_dict()
    (analysis,) = data["analyses"]
    assert [f["field"] for f in analysis["fields"]] == [r["field"] for r in analysis["ranking"]]
    for f in analysis["fields"]:
        for v in f["values"]:
            assert v["ci95_low"] <= v["success_rate"] <= v["ci95_high"]
            assert v["episodes"] == 10
    assert data["planned"] == data["episodes"] == 70
    assert data["episodes_per_s"] == 35.0


def png_size(path):
    head = path.read_bytes()[:24]
    assert head[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", head[16:24])


def test_the_figure_has_a_panel_per_field_and_the_tornado(tmp_path):
    pytest.importorskip("matplotlib")
    one = tmp_path / "one.png"
    plot_sensitivity(synthetic_result(), one)
    width, height = png_size(one)
    assert width > 1000 and height > 300  # projector-sized
    # more fields, more panels: the figure grows
    plan = plan_for(values=2, seeds=range(2))
    outcomes = outcomes_for(plan, [1] * len(plan.points))
    sweep = SweepResult(plan=plan.sweep, outcomes=outcomes, ran=len(outcomes), wall_s=1.0)
    many = tmp_path / "many.png"
    plot_sensitivity(SensitivityResult.of(plan, sweep), many)
    assert png_size(many)[1] > height


@pytest.fixture(scope="session")
def repo_root():
    from pathlib import Path

    return Path(__file__).resolve().parents[2]


def test_points_survive_a_round_trip_through_a_csv_row(tmp_path):
    """Keys read back from --out match the plan's points however the numbers were spelt."""
    plan = plan_for(fields=["ir_gain"], values=3)
    point = next(p for p in plan.points if p.kind == VALUE)
    read_back = json.loads(json.dumps(dict(point.params)))
    assert params_key(read_back) == plan.point_key(point)
    assert params_key({**read_back, "profile.ir_gain": 0.7}) == plan.point_key(point)
    unused = dataclasses.replace(point, params={"robot.profile": "epuck"})
    assert plan.point_key(unused) != plan.point_key(point)
