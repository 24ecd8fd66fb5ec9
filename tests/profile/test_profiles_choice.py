"""Choosing a robot profile: per scene, per robot, per run, per sweep; reports name it."""

from __future__ import annotations

import json

import pytest

from puckboard.cli import main
from puckboard.control.episode import run_episode
from puckboard.scenario import scene_from_dict
from puckboard.sim.world import World
from puckboard.sweep.plan import PlanError, parse_set

TRACK = {"shape": "stadium", "length": 0.8, "radius": 0.25}


def two_robots(**top):
    return scene_from_dict(
        {
            "track": TRACK,
            **top,
            "robots": [
                {"name": "a", "track_position": 0.0, "direction": "along"},
                {"name": "b", "track_position": 0.5, "direction": "along", "profile": "epuck"},
            ],
        }
    )


def test_a_scene_names_a_default_profile_and_a_robot_may_differ():
    scene = two_robots(profile="epuck-vrep")
    assert [r.profile for r in scene.robots] == ["epuck-vrep", "epuck"]
    assert [r.profile for r in two_robots().robots] == ["epuck", "epuck"]


def test_one_world_mixes_cone_and_ray_sensing():
    world = World(two_robots(profile="epuck-vrep"))
    assert [p.name for p in world.profiles] == ["epuck-vrep", "epuck"]
    ir = world.sensing.ir
    assert ir["cone"].robots == (0,)  # only the V-REP robot senses with cones
    assert ir["rays"].robots == (1,)  # and the other with rays


def test_shipped_thesis_scenes_use_vrep_s_model_and_arena_the_physical_robot():
    from puckboard.scenario import load_scene

    for name in ("two-robot-pass", "two-robot-pass-bend", "line-follow"):
        assert {r.profile for r in load_scene(name).robots} == {"epuck-vrep"}, name
    assert {r.profile for r in load_scene("arena").robots} == {"epuck"}


def test_run_profile_overrides_the_scene_and_the_report_names_it(capsys):
    assert main(["run", "line-follow", "--profile", "epuck", "--duration", "1", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert [r["profile"] for r in report["robots"]] == ["epuck"]
    result = run_episode("line-follow", duration=1.0)
    assert [m.profile for m in result.robots] == ["epuck-vrep"]


def test_an_unknown_profile_is_one_line_naming_the_known_ones(capsys):
    assert main(["run", "line-follow", "--profile", "epuck3", "--duration", "1"]) == 2
    err = capsys.readouterr().err.strip()
    assert "unknown robot profile 'epuck3'" in err and "epuck-vrep" in err
    assert len(err.splitlines()) == 1


def test_sweeps_vary_the_profile_and_refuse_unknown_ones():
    assert parse_set("robot.profile=epuck,epuck-vrep") == ("robot.profile", ("epuck", "epuck-vrep"))
    with pytest.raises(PlanError, match="unknown profile 'nope'"):
        parse_set("robot.profile=epuck,nope")


def test_profiles_command_lists_every_profile_with_sources(capsys):
    assert main(["profiles", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert [r["name"] for r in rows] == ["epuck", "epuck-vrep", "e-puck1"]
    vrep = rows[1]
    assert vrep["ir_model"] == "cone" and vrep["ir_detects_mm"] == [1.5, 41.5]
    assert all(vrep["sources"].values())
    assert main(["profiles", "show", "nope"]) == 2
