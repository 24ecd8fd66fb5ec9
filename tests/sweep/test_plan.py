"""Sweep plans: --seeds and --set parsing, their errors, and the combinations."""

from __future__ import annotations

import pytest

from puckboard.sweep.plan import (
    SCENE_CONTROLLERS,
    PlanError,
    SweepPlan,
    episode_key,
    parse_seeds,
    parse_set,
)


def test_seeds_are_a_python_range():
    assert parse_seeds("0:5") == range(0, 5)
    assert list(parse_seeds("3:9:3")) == [3, 6]


@pytest.mark.parametrize(
    ("spec", "message"),
    [
        ("5", "expected A:B"),
        ("a:b", "whole numbers"),
        ("5:5", "is empty"),
        ("9:2", "is empty"),
        ("0:4:0", "STEP cannot be 0"),
        ("-3:2", "cannot be negative"),
        ("1:2:3:4", "expected A:B"),
    ],
)
def test_bad_seeds_say_what_is_wrong(spec, message):
    with pytest.raises(PlanError, match=message):
        parse_seeds(spec)


def test_set_parses_names_and_values():
    assert parse_set("noise.proximity=0, 0.05,0.1") == ("noise.proximity", (0, 0.05, 0.1))
    name, values = parse_set("layer.LineFollow.recovery=true,false")
    assert name == "layer.LineFollow.recovery"
    assert values == (True, False)


@pytest.mark.parametrize(
    ("spec", "message"),
    [
        ("noise.proximity", "expected PARAM=V1,V2"),
        ("=1,2", "expected PARAM=V1,V2"),
        ("noise.proximty=0.1", "unknown parameter 'noise.proximty'"),
        ("gain=1", "unknown parameter"),
        ("layer.LineFollow=1", "unknown parameter"),
        ("noise.ground=", "no values"),
        ("noise.ground=high", "parameter noise.ground = 'high': expected a number"),
        ("noise.ground=-0.1", r"parameter noise.ground = -0.1: outside \[0, 1\]"),
        ("dt=0", r"parameter dt = 0: outside \(0, 1\] s \(simulation step\)"),
        ("duration=nan", r"parameter duration = nan: outside \(0, 1e\+06\] s"),
        ("control.latency=1e9", r"control.latency = 1e\+09: outside \[0, 1\] s"),
        ("control.period=100ms,50ms", None),
        ("noise.ground=0.1,0.10", "listed twice"),
    ],
)
def test_bad_set_specs_say_what_is_wrong(spec, message):
    if message is None:  # a time with its unit, as every setting takes it
        assert parse_set(spec) == ("control.period", (0.1, 0.05))
        return
    with pytest.raises(PlanError, match=message):
        parse_set(spec)


def test_plan_is_the_full_product_in_a_stable_order():
    plan = SweepPlan.from_specs(
        "arena",
        controllers=["stock", "improved"],
        seeds="0:3",
        sets=["noise.proximity=0,0.1", "layer.Cruise.speed=1,2"],
        fixed={"duration": 5},
    )
    episodes = list(plan.episodes())
    assert len(plan) == len(episodes) == 2 * 2 * 2 * 3
    assert len({e.key("arena") for e in episodes}) == len(episodes)
    assert episodes[0].controller == "stock" and episodes[-1].controller == "improved"
    assert all(e.param_dict["duration"] == 5 for e in episodes)
    assert plan.swept == ("noise.proximity", "layer.Cruise.speed")
    assert list(plan.episodes()) == episodes


def test_plan_defaults_to_the_scene_controllers_and_rejects_repeats():
    plan = SweepPlan.from_specs("arena", seeds="0:2")
    assert plan.controllers == (SCENE_CONTROLLERS,)
    with pytest.raises(PlanError, match="given twice"):
        SweepPlan.from_specs("arena", sets=["dt=0.05", "dt=0.1"])
    with pytest.raises(PlanError, match="listed twice"):
        SweepPlan.from_specs("arena", controllers=["stock", "stock"])
    with pytest.raises(PlanError, match="both swept and fixed"):
        SweepPlan.from_specs("arena", sets=["duration=5,6"], fixed={"duration": 5})


def test_episode_identity_ignores_spelling_of_equal_numbers():
    a = episode_key("arena", "stock", 1, {"dt": 0.05, "duration": 2})
    b = episode_key("arena", "stock", 1, {"duration": 2.0, "dt": 0.05})
    assert a == b
    assert a != episode_key("arena", "stock", 2, {"dt": 0.05, "duration": 2})
    assert a != episode_key("arena", "improved", 1, {"dt": 0.05, "duration": 2})
    assert a != episode_key("line-follow", "stock", 1, {"dt": 0.05, "duration": 2})


def test_batches_cover_the_plan_in_order_and_stay_small():
    from puckboard.sweep.run import MAX_BATCH, make_batches

    specs = list(SweepPlan.from_specs("arena", seeds="0:100").episodes())
    for workers in (1, 2, 8):
        batches = make_batches(specs, workers)
        assert [s for b in batches for s in b] == specs
        assert max(len(b) for b in batches) <= MAX_BATCH
        assert len(batches) >= min(len(specs), 2 * workers)  # every worker gets several
    assert [len(b) for b in make_batches(specs[:5], 2, batch_size=2)] == [2, 2, 1]
    with pytest.raises(ValueError, match="at least 1"):
        make_batches(specs, 2, batch_size=0)


def test_automatic_batches_shrink_to_single_episodes_at_the_end():
    """The end of a sweep is single episodes: no worker finishes on a long batch."""
    from puckboard.sweep.batches import TASKS_PER_WORKER, make_batches

    specs = list(SweepPlan.from_specs("arena", seeds="0:192").episodes())
    for workers in (1, 2, 16):
        sizes = [len(b) for b in make_batches(specs, workers)]
        assert sizes == sorted(sizes, reverse=True)
        assert sizes[-TASKS_PER_WORKER * workers :] == [1] * min(len(sizes), 4 * workers)
        remaining = len(specs)
        for size in sizes:  # never more than 1/(4 W) of what is left (or one episode)
            assert size <= max(1, -(-remaining // (TASKS_PER_WORKER * workers)))
            remaining -= size
    assert len(make_batches(specs, 16)) > len(specs) // 3  # earlier: 64 batches of 3


def test_balanced_order_puts_longer_episodes_first_and_mixes_the_groups():
    from types import SimpleNamespace

    from puckboard.sweep.batches import balance_order

    scene = SimpleNamespace(duration=20.0, dt=0.05)
    plan = SweepPlan.from_specs(
        "arena",
        controllers=["stock", "improved"],
        seeds="0:3",
        sets=["duration=5,40", "noise.ground=0,0.1"],
    )
    specs = list(plan.episodes())
    ordered = balance_order(specs, scene)
    assert sorted(ordered, key=specs.index) == specs  # the same episodes, each once
    durations = [s.param_dict["duration"] for s in ordered]
    assert durations == sorted(durations, reverse=True)
    # within one step limit: one episode of each of the 4 groups in turn, seed by seed
    long = [s for s in ordered if s.param_dict["duration"] == 40]
    groups = {(s.controller, s.params) for s in long}
    assert len(groups) == 4
    for k in range(3):
        round_k = long[4 * k : 4 * k + 4]
        assert {(s.controller, s.params) for s in round_k} == groups
        assert {s.seed for s in round_k} == {k}
    # a dt parameter changes the step limit as duration does
    dts = SweepPlan.from_specs("arena", seeds="0:2", sets=["dt=0.1,0.01"]).episodes()
    assert [s.param_dict["dt"] for s in balance_order(list(dts), scene)] == [0.01] * 2 + [0.1] * 2


def test_seeds_are_written_as_they_are_read_in_one_place():
    from puckboard.sweep.plan import parse_seeds, seeds_text

    for text in ("0:20", "5:40:5"):
        assert seeds_text(parse_seeds(text)) == text
    assert seeds_text([3, 1, 2, 2]) == "1:4"  # rows read back: consecutive seeds
    assert seeds_text([0, 2, 7]) == "3 seeds"
    assert seeds_text([]) == ""
