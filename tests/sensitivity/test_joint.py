"""The joint sensitivity method: its estimators on data whose answer is known, rows read
back, and the figures' legends."""

from __future__ import annotations

import json

import numpy as np
import pytest

from puckboard.profile import get_profile, profile_values
from puckboard.sensitivity.joint import analyse_rows, from_rows, joint_plan
from puckboard.sensitivity.joint.estimate import (
    PASS,
    PROGRESS,
    binned_curve,
    main_effect,
    ranking_outcome,
)
from puckboard.sensitivity.one_at_a_time.plan import FIELD_LABEL
from puckboard.sweep import PlanError
from puckboard.sweep.options import RunOptions

PATHS = ("body_radius", "ir_gain.right", "prox_heading.diagonal_right", "axle_length")


def synthetic_rows(n: int, driver: str | None, seed: int = 1) -> list[dict]:
    """Rows as a joint run writes them: two robots, four drawn numbers each (within
    ±10 % of the shipped value), success driven by the left robot's ``driver`` (its
    rate from 0.7 at the low end to 0.1 at the high end), or by nothing."""
    rng = np.random.default_rng(seed)
    shipped = profile_values(get_profile("epuck"))
    rows = []
    for s in range(n):
        robots = {
            robot: {p: shipped[p] * rng.uniform(0.9, 1.1) for p in PATHS}
            for robot in ("left", "right")
        }
        rate = 0.3
        if driver is not None:
            u = (robots["left"][driver] / shipped[driver] - 0.9) / 0.2
            rate = 0.7 - 0.6 * (u if shipped[driver] > 0 else 1 - u)
        success = bool(rng.uniform() < rate)
        params = {"robot.profile": "epuck", "variation": "plausible"}
        row = {
            "key": f"k{s}",
            "scenario": "two-robot-pass",
            "controller": "improved",
            "seed": s,
            "params": json.dumps(params, sort_keys=True),
            "success": success,
            "failure": "" if success else "collision",
            "progress_laps": (0.6 if success else 0.3) + rng.normal(0, 0.05),
        }
        for robot, values in robots.items():
            row[f"robot.{robot}.profile_values"] = json.dumps(values)
        rows.append(row)
    return rows


def test_a_number_that_drives_the_outcome_is_ranked_first_and_clear():
    (a,) = analyse_rows(synthetic_rows(300, "ir_gain.right"))
    assert a.band.episodes == 300
    assert a.ranked_by == PASS
    assert [n.name for n in a.clear] == ["left: ir_gain.right"]
    assert a.ranking[0].name == "left: ir_gain.right"
    effect = a.ranking[0].effect(PASS)
    assert effect is not None and effect.high < 0  # the rate falls as the gain rises
    bins = a.ranking[0].bins
    assert len(bins) == 4 and sum(b.episodes for b in bins) == 300
    assert bins[0].interval[0] > bins[-1].interval[1]  # the ends' Wilson intervals apart
    data = a.to_dict()
    assert data["clear"] == ["left: ir_gain.right"]
    assert data["ranking"][0] == {"number": "left: ir_gain.right", "clear": True,
                                  "estimate": effect.estimate, "ci_low": effect.low,
                                  "ci_high": effect.high}  # fmt: skip
    assert len(data["numbers"]) == 2 * len(PATHS)


def test_pure_noise_says_nothing_is_clear_and_ranks_nothing():
    (a,) = analyse_rows(synthetic_rows(300, None))
    assert a.clear == []
    data = a.to_dict()
    assert data["ranking"] == [] and data["verdict"] == "nothing is clear at N = 300"
    assert data["interaction"] is not None and data["interaction"]["clear"] is False
    # every number still has its curve and its index with an interval around 0
    for number in data["numbers"]:
        index = number["index"][PASS]
        assert index["ci_low"] < 0 < index["ci_high"]
        assert len(number["bins"]) == 4


def test_rare_passes_rank_by_progress():
    assert ranking_outcome(np.array([1.0] * 9 + [0.0] * 291)) == PROGRESS
    assert ranking_outcome(np.array([1.0] * 10 + [0.0] * 290)) == PASS
    assert ranking_outcome(np.array([1.0] * 295 + [0.0] * 5)) == PROGRESS


def test_intervals_are_simultaneous_over_the_numbers_tested():
    rng = np.random.default_rng(3)
    x = rng.uniform(size=400)
    y = 2.0 * x + rng.normal(0, 1, size=400)
    one, sixty = main_effect(x, y, PROGRESS, 1), main_effect(x, y, PROGRESS, 60)
    assert one is not None and sixty is not None
    assert one.estimate == sixty.estimate
    assert sixty.low < one.low < one.high < sixty.high
    assert main_effect(np.ones(10), y[:10], PROGRESS, 1) is None  # a number that never varies


def test_bins_hold_every_episode_once_with_their_ranges():
    x = np.arange(10.0)
    bins = binned_curve(x, (x > 4).astype(float), x / 10, 2)
    assert [(b.low, b.high, b.episodes, b.successes) for b in bins] == [(0, 4, 5, 0), (5, 9, 5, 5)]
    assert bins[1].rate == 1.0 and bins[1].interval[0] < 1.0


def test_rows_of_other_points_are_left_out_and_from_rows_says_what_it_needs():
    rows = synthetic_rows(40, None)
    moved = dict(rows[0], key="other", params=json.dumps(
        {"robot.profile": "epuck", "variation": "plausible", "profile.ir_gain": 0.7,
         FIELD_LABEL: "ir_gain"}))  # fmt: skip
    shipped = dict(rows[1], key="shipped", params=json.dumps({"robot.profile": "epuck"}))
    (a,) = analyse_rows([*rows, moved, shipped])
    assert a.band.episodes == 40
    result = from_rows(rows)
    assert (result.scenario, result.seeds, result.profiles) == (
        "two-robot-pass",
        "0:40",
        ("epuck",),
    )
    with pytest.raises(PlanError, match="no rows of plausible robots"):
        from_rows([shipped])


def test_the_joint_plan_is_the_plausible_point_of_each_profile():
    plan = joint_plan("two-robot-pass", profiles=["epuck", "epuck-vrep"],
                      controllers=["improved"], seeds=range(0, 300))  # fmt: skip
    assert plan.sweep.points == (
        {"robot.profile": "epuck", "variation": "plausible"},
        {"robot.profile": "epuck-vrep", "variation": "plausible"},
    )
    assert len(plan) == 600
    with pytest.raises(PlanError, match="too few for 4 bins"):
        joint_plan("two-robot-pass", profiles=["epuck"], controllers=["improved"], seeds=range(5))


def test_the_one_at_a_time_legend_draws_every_mark_as_the_chart_does():
    pytest.importorskip("matplotlib")
    from types import SimpleNamespace

    from puckboard.sensitivity.one_at_a_time.plot import legend_entries
    from puckboard.viz.figures import COLOURS

    analyses = [SimpleNamespace(controller=c, profile="epuck", shipped=None, plausible=None)
                for c in ("a", "b")]  # fmt: skip
    handles, labels = legend_entries(analyses, {"a": "a", "b": "b"})  # type: ignore[arg-type]
    dotted = handles[labels.index("dotted line: plausible robots' rate")]
    assert [h.get_color() for h in dotted] == list(COLOURS[:2])  # not grey: each its colour
    assert [h.get_linestyle() for h in dotted] == [":", ":"]
    assert "dashed grey line: the shipped value" in labels
    dark = handles[labels.index("dark bar: lowest and highest rates' 95 % intervals apart (clear)")]
    pale = handles[labels.index("pale bar: they overlap (not clear)")]
    assert [h.get_alpha() for h in dark] == [1.0, 1.0]
    assert [h.get_alpha() for h in pale] == [0.35, 0.35]


def test_ctrl_c_keeps_what_ran_and_analyses_it(short_scene):
    from sweep_helpers import DURATION, CountingExecutor

    from puckboard.sensitivity.joint import run_joint

    plan = joint_plan(short_scene.name, profiles=["epuck"], controllers=["stock"],
                      seeds=range(8), fixed={"duration": DURATION}, bins=2)  # fmt: skip
    result = run_joint(
        plan, short_scene, RunOptions(executor=CountingExecutor(interrupt_after=3), batch_size=1)
    )
    assert result.sweep.interrupted and result.sweep.ran == 3
    (analysis,) = result.analyses
    assert analysis.band.episodes == 3
    assert all(sum(b.episodes for b in n.bins) == 3 for n in analysis.numbers)
