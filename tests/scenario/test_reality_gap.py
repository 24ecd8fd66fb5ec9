"""Conditions as settings (--set surface.*, obstacle.*, start.*) and --variation
reality-gap: plausible robots as plausible draws them, in conditions drawn within their
ranges."""

from __future__ import annotations

import math

import pytest

from puckboard.control.episode import run_episode
from puckboard.profile.links import get_link
from puckboard.scenario.conversion import scene_from_dict, scene_to_dict
from puckboard.scenario.overrides import apply_scene_overrides
from puckboard.scenario.reality_gap import CONDITION_RANGES, REAL_LINKS, draw_conditions
from puckboard.scenario.scenefile import load_scene
from puckboard.scenario.variation import vary_scene

PASS = load_scene("two-robot-pass")


def test_line_and_obstacle_settings_change_the_scene():
    scene = apply_scene_overrides(
        PASS,
        {"surface.line_width": 0.019, "surface.line_contrast": 0.6, "obstacle.ir_reflectance": 0.2},
    )
    assert scene.track is not None and PASS.track is not None
    assert (scene.track.width, scene.track.contrast) == (0.019, 0.6)
    assert (scene.track.points == PASS.track.points).all()
    assert [ob.ir_reflectance for ob in scene.obstacles] == [0.2, 0.2]


def test_a_hand_placement_moves_each_robot_to_its_own_left_and_turns_it():
    scene = apply_scene_overrides(PASS, {"start.offset": 0.01, "start.heading": 0.1})
    left, right = scene.robots
    # left heads +x (its left is +y), right heads -x (its left is -y)
    assert left.y == pytest.approx(PASS.robots[0].y + 0.01)
    assert right.y == pytest.approx(PASS.robots[1].y - 0.01)
    assert left.theta == pytest.approx(PASS.robots[0].theta + 0.1)
    assert math.cos(right.theta - PASS.robots[1].theta) == pytest.approx(math.cos(0.1))


@pytest.mark.parametrize(
    ("overrides", "message"),
    [
        ({"surface.line_contrast": 1.5}, r"surface.line_contrast = 1.5: outside \[0, 1\]"),
        ({"obstacle.ir_reflectance": "black"}, "obstacle.ir_reflectance = 'black': expected a"),
        ({"start.offset": 0.5}, r"start.offset = 0.5: outside \[-0.1, 0.1\] m"),
    ],
)
def test_bad_condition_values_are_one_line(overrides, message):
    with pytest.raises(ValueError, match=message) as info:
        apply_scene_overrides(PASS, overrides)
    assert "\n" not in str(info.value)


def test_a_line_setting_needs_a_line():
    with pytest.raises(ValueError, match="has no line"):
        apply_scene_overrides(load_scene("arena"), {"surface.line_width": 0.02})


def test_contrast_and_reflectance_survive_a_scene_file_and_defaults_are_not_written():
    assert "contrast" not in scene_to_dict(PASS)["track"]
    assert all("ir_reflectance" not in ob for ob in scene_to_dict(PASS)["obstacles"])
    changed = apply_scene_overrides(
        PASS, {"surface.line_contrast": 0.7, "obstacle.ir_reflectance": 0.3}
    )
    again = scene_from_dict(scene_to_dict(changed))
    assert again.track is not None and again.track.contrast == 0.7
    assert [ob.ir_reflectance for ob in again.obstacles] == [0.3, 0.3]


def test_reality_gap_robots_are_the_plausible_robots_of_the_same_seed():
    for seed in (0, 7):
        plausible = vary_scene(PASS, seed, "plausible")
        gap = vary_scene(PASS, seed, "reality-gap")
        assert [r.actual for r in gap.robots] == [r.actual for r in plausible.robots]
        assert gap.robots[0].actual is not None


def test_conditions_lie_in_their_ranges_and_follow_the_seed():
    drawn = [draw_conditions(PASS, seed).to_dict() for seed in range(40)]
    for conditions in drawn:
        link = get_link(conditions.pop("control.link"))
        assert conditions.pop("control.period") >= link.period[0] - 0.05  # whole steps
        assert conditions.pop("control.latency") <= link.latency[1] + 0.025
        for name, value in conditions.items():
            r = CONDITION_RANGES[name]
            for v in value.values() if isinstance(value, dict) else [value]:
                assert r.low <= v <= r.high, name
    assert draw_conditions(PASS, 3) == draw_conditions(PASS, 3)
    assert len({d["surface.line_width"] for d in drawn}) == 40
    # each obstacle and each robot draws its own
    first = drawn[0]
    assert len(set(first["obstacle.ir_reflectance"].values())) == 2
    assert len(set(first["start.offset"].values())) == 2


def test_conditions_the_run_sets_are_kept_and_the_others_do_not_move():
    free = draw_conditions(PASS, 5).to_dict()
    kept = draw_conditions(PASS, 5, fixed=["noise.ground", "start.offset"]).to_dict()
    assert "noise.ground" not in kept and "start.offset" not in kept
    assert kept["surface.line_width"] == free["surface.line_width"]
    assert kept["start.heading"] == free["start.heading"]
    scene = vary_scene(
        apply_scene_overrides(PASS, {"noise.ground": 0.2}), 5, "reality-gap", ["noise.ground"]
    )
    assert scene.noise.ground == 0.2
    assert scene.noise.proximity == free["noise.proximity"]


def test_the_result_reports_conditions_only_when_reality_gap_drew_them():
    gap = run_episode("two-robot-pass", seed=2, duration=0.2, variation="reality-gap").to_dict()
    plain = run_episode("two-robot-pass", seed=2, duration=0.2, variation="plausible").to_dict()
    assert "conditions" not in plain
    assert gap["conditions"] == draw_conditions(PASS, 2).to_dict()


def test_the_link_timing_comes_from_a_real_robot_s_link():
    drawn = [draw_conditions(PASS, seed).to_dict() for seed in range(60)]
    assert {d["control.link"] for d in drawn} == set(REAL_LINKS)
    scene = vary_scene(PASS, 4, "reality-gap")
    assert scene.control.period == drawn[4]["control.period"]
    assert scene.control.latency == drawn[4]["control.latency"]
    scene.control.steps(scene.dt)  # whole steps of the scene's dt
    kept = vary_scene(
        apply_scene_overrides(PASS, {"control.period": 0.1}), 4, "reality-gap", ["control.period"]
    )
    assert kept.control.period == 0.1 and kept.control.latency == drawn[4]["control.latency"]


def test_the_text_report_lists_the_drawn_conditions_only_for_reality_gap(capsys):
    from puckboard.cli import main

    args = ["run", "two-robot-pass", "--seed", "3", "--duration", "0.2"]
    assert main([*args, "--variation", "reality-gap"]) == 0
    out = capsys.readouterr().out
    drawn = draw_conditions(PASS, 3).to_dict()
    assert "conditions drawn (reality-gap):" in out
    assert f"control.link = {drawn['control.link']}" in out
    assert main([*args, "--variation", "plausible"]) == 0
    assert "conditions drawn" not in capsys.readouterr().out
