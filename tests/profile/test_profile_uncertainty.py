"""Plausible ranges and plausible robots: cited, reproducible, independent per robot."""

from __future__ import annotations

import numpy as np
import pytest

from puckboard.profile import (
    EPUCK,
    EPUCK1,
    EPUCK_VREP,
    PROFILES,
    apply_overrides,
    check_value,
    draw,
    profile_values,
    uncertainty,
    variation_rng,
)
from puckboard.profile.setting_names import expand_setting, setting_value
from puckboard.profile.uncertainty import RANGE_KINDS, VARIATION_STREAM
from puckboard.scenario import load_scene
from puckboard.scenario.variation import vary_scene


@pytest.mark.parametrize("name", list(PROFILES))
def test_every_range_cites_its_bounds_and_holds_the_shipped_value(name):
    profile = PROFILES[name]
    for path, plausible in uncertainty(profile).items():
        assert plausible.kind in RANGE_KINDS
        assert len(plausible.source) > 20, path
        assert plausible.low < plausible.high, path
        check_value(path, plausible.low), check_value(path, plausible.high)  # physical sense
        for single in expand_setting(path):
            value = setting_value(profile, single)
            if path.startswith("prox_heading."):
                value = abs(value)  # a pair's range is the left sensor's heading
            assert plausible.low - 1e-12 <= value <= plausible.high + 1e-12, (path, single)


def test_the_physical_robots_share_ranges_and_v_rep_s_model_has_only_its_variants():
    assert uncertainty(EPUCK1) == uncertainty(EPUCK)
    assert {"prox_radius.side", "prox_max_distance", "ir_gain"} <= set(uncertainty(EPUCK))
    vrep = uncertainty(EPUCK_VREP)
    assert set(vrep) == {"body_radius"} and vrep["body_radius"].kind == "decoded variants"
    assert (vrep["body_radius"].low, vrep["body_radius"].high) == (0.0352, 0.0362)


def test_a_profile_file_keeps_the_ranges_of_the_profile_it_changes():
    mine = apply_overrides(EPUCK, {"ir_gain.right": 0.83}, source="measured")
    assert uncertainty(mine) == uncertainty(EPUCK)


def test_a_draw_is_uniform_within_every_range_and_the_same_for_the_same_generator():
    a = draw(EPUCK, variation_rng(3, 0))
    b = draw(EPUCK, variation_rng(3, 0))
    assert a == b
    values = profile_values(a)
    for path, plausible in uncertainty(EPUCK).items():
        for single in expand_setting(path):
            value = abs(values[single]) if path.startswith("prox_heading.") else values[single]
            assert plausible.low <= value <= plausible.high, single
    # many robots fill the range: no bound chosen by anything but the range
    gains = [draw(EPUCK, variation_rng(seed, 0)).ir_gain[0] for seed in range(200)]
    assert min(gains) < 0.75 and max(gains) > 1.25


def test_two_robots_of_one_run_differ_and_each_sensor_is_drawn_on_its_own():
    first, second = (draw(EPUCK, variation_rng(3, i)) for i in (0, 1))
    assert first.ir_gain != second.ir_gain
    assert len(set(first.ir_gain)) == 8
    assert first.wheel_radii[0] != first.wheel_radii[1]


def test_numbers_a_profile_sets_are_not_drawn_and_the_others_draw_as_before():
    mine = apply_overrides(EPUCK, {"prox_max_distance": 0.045}, source="measured")
    drawn_mine = draw(mine, variation_rng(5, 0))
    drawn_shipped = draw(EPUCK, variation_rng(5, 0))
    assert drawn_mine.prox_max_distance == 0.045
    assert drawn_mine.ir_gain == drawn_shipped.ir_gain  # the same stream, draw for draw
    assert drawn_mine.sources["prox_max_distance"] == "measured"


def test_the_variation_stream_is_its_own():
    expected = np.random.default_rng([7, 1, VARIATION_STREAM]).uniform(size=3)
    assert variation_rng(7, 1).uniform(size=3).tolist() == expected.tolist()
    assert variation_rng(7, 1).uniform() != np.random.default_rng(7).uniform()


def test_a_varied_scene_gives_each_robot_its_truth_and_keeps_its_belief():
    scene = load_scene("arena")
    varied = vary_scene(scene, 3, "plausible")
    assert [r.profile for r in varied.robots] == [r.profile for r in scene.robots]
    truths = [r.actual for r in varied.robots]
    assert all(t is not None for t in truths)
    assert truths[0] == draw(EPUCK, variation_rng(3, 0))
    assert truths[1] == draw(EPUCK, variation_rng(3, 1))
    assert vary_scene(scene, 3, "none") is scene
    # a truth the scene already holds (a recording of a varied run) is kept
    assert vary_scene(varied, 4, "plausible").robots[0].actual == truths[0]
    with pytest.raises(ValueError, match="unknown variation 'wild'; use one of none, plausible"):
        vary_scene(scene, 3, "wild")


def test_the_judge_measures_the_robots_as_built():
    from puckboard.scenario.judge import Judge

    varied = vary_scene(load_scene("arena"), 3, "plausible")
    judge = Judge(varied)
    truths = [r.actual for r in varied.robots]
    assert [r.radius for r in judge.robots] == [t.body_radius for t in truths]
    assert [m.profile_values for m in judge.metrics()] == [profile_values(t) for t in truths]
    assert [m.profile for m in judge.metrics()] == ["epuck", "epuck"]
