"""Scene files: the shipped scenes load, the schema refuses mistakes and names the field."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest

from puckboard.errors import SceneError
from puckboard.scenario import load_scene, scene_from_dict, scene_names, scene_to_dict
from puckboard.scenario.scene import CircleObstacle
from puckboard.scenario.scenefile import parse_scene_text


def minimal(**extra):
    data = {"robots": [{"name": "r", "x": 0.0, "y": 0.0, "theta": 0.0}]}
    data.update(extra)
    return data


def test_the_shipped_scenes_are_there_and_load():
    assert {"two-robot-pass", "line-follow", "arena"} <= set(scene_names())
    for name in scene_names():
        scene = load_scene(name)
        assert scene.name == name
        assert scene.description
        assert scene.noise.wheel_speed > 0 and scene.noise.proximity > 0  # seeds matter


def test_two_robot_pass_geometry():
    scene = load_scene("two-robot-pass")
    assert scene.goal.resolve(scene) == "pass"
    left, right = scene.robots
    # on the line, 0.5 m apart, facing each other
    assert left.y == pytest.approx(right.y) == pytest.approx(-0.25)
    assert right.x - left.x == pytest.approx(0.5)
    assert math.cos(left.theta) == pytest.approx(1.0)
    assert math.cos(right.theta) == pytest.approx(-1.0)
    assert len(scene.obstacles) == 2
    # the stadium: 2 × 0.8 m straights + a 0.25 m radius circle
    assert scene.track.length == pytest.approx(1.6 + 2 * math.pi * 0.25, rel=1e-3)


def test_load_by_path_toml_and_json(tmp_path):
    toml = tmp_path / "mine.toml"
    toml.write_text("[[robots]]\nx = 0.1\ny = 0.2\ntheta_deg = 90\n", encoding="utf-8")
    scene = load_scene(toml)
    assert scene.name == "mine"
    assert scene.robots[0].theta == pytest.approx(math.pi / 2)
    assert scene.robots[0].name == "epuck1"
    js = tmp_path / "mine.json"
    js.write_text(json.dumps(minimal(name="j")), encoding="utf-8")
    assert load_scene(str(js)).name == "j"


def test_round_trip_through_dict_keeps_the_scene():
    scene = load_scene("two-robot-pass")
    again = scene_from_dict(json.loads(json.dumps(scene_to_dict(scene))))
    assert again.name == scene.name
    assert np.allclose(again.track.points, scene.track.points)
    assert np.allclose(
        [(r.x, r.y, r.theta) for r in again.robots], [(r.x, r.y, r.theta) for r in scene.robots]
    )
    assert again.noise == scene.noise and again.goal == scene.goal
    assert isinstance(again.obstacles[0], CircleObstacle)
    assert all(isinstance(o, CircleObstacle) for o in again.obstacles)


def test_robots_and_obstacles_on_the_track():
    scene = scene_from_dict(
        {
            "track": {"shape": "circle", "radius": 0.5},
            "robots": [
                {"name": "a", "track_position": 0.25, "direction": "along"},
                {"name": "b", "track_distance": 0.0, "direction": "against"},
            ],
            "obstacles": [{"shape": "box", "track_position": 0.5, "size": [0.05, 0.05]}],
        }
    )
    a, b = scene.robots
    # the circle starts at the bottom and runs counter-clockwise: a quarter is on the right
    assert (a.x, a.y) == pytest.approx((0.5, 0.0), abs=2e-3)
    assert math.sin(a.theta) == pytest.approx(1.0, abs=1e-3)  # heading up (+y)
    assert (b.x, b.y) == pytest.approx((0.0, -0.5), abs=2e-3)
    assert math.cos(b.theta) == pytest.approx(-1.0, abs=1e-3)
    box = scene.obstacles[0]
    assert np.allclose(box.vertices.mean(axis=0), (0.0, 0.5), atol=2e-3)


@pytest.mark.parametrize(
    ("data", "expected"),
    [
        (
            {"robots": [{"x": 0, "y": 0, "theta": 0}, {"x": 1, "y": 0, "theta": "north"}]},
            "robots[1].theta: expected a number (radians), got 'north'",
        ),
        ({"robots": [{"x": 0, "y": 0}]}, "robots[0].theta: missing"),
        ({"robots": [{"x": 0, "theta": 0}]}, "robots[0].y: missing"),
        ({"robots": []}, "robots: expected at least one robot"),
        ({}, "robots: missing"),
        (minimal(dt=0), "dt: expected a number > 0 (s)"),
        (minimal(dt=True), "dt: expected a number (s), got True"),
        (minimal(durration=5), "durration: unknown key"),
        (minimal(noise={"wheel_speed": -0.1}), "noise.wheel_speed: expected a number >= 0"),
        (minimal(noise={"wheels": 0.1}), "noise.wheels: unknown key"),
        (minimal(track={"shape": "blob"}), "track.shape: expected one of points, stadium"),
        (minimal(track={"shape": "stadium", "length": 1}), "track.radius: missing"),
        (minimal(track={"points": [[0, 0], [1, "a"]]}), "track.points[1]: expected an [x, y] pair"),
        (minimal(track={"points": [[0, 0]]}), "track.points: expected a list of at least 2"),
        (
            minimal(obstacles=[{"shape": "circle", "x": 0, "y": 0, "radius": -1}]),
            "obstacles[0].radius: expected a number > 0.001",
        ),
        (
            minimal(
                obstacles=[{"shape": "polygon", "vertices": [[0, 0], [1, 0], [0.2, 0.2], [0, 1]]}]
            ),
            "obstacles[0].vertices: the polygon must be convex",
        ),
        (
            minimal(arena={"xmin": 1, "ymin": 0, "xmax": 0, "ymax": 1}),
            "arena.xmax: expected a number > xmin",
        ),
        (minimal(floor_colour=[0, 0, 300]), "floor_colour: expected an [r, g, b] colour"),
        (minimal(goal={"kind": "dance"}), "goal.kind: expected one of auto, pass, follow, avoid"),
        (minimal(goal={"kind": "pass"}), "goal.kind: goal 'pass' needs a [track]"),
        (
            {"robots": [{"track_position": 0.1, "direction": "along"}]},
            "robots[0].track_position: the scene has no [track] to place on",
        ),
        (
            {"robots": [{"x": 0, "y": 0, "theta": 0, "theta_deg": 0}]},
            "robots[0].theta: give either theta (radians) or theta_deg, not both",
        ),
        (
            {
                "robots": [
                    {"name": "a", "x": 0, "y": 0, "theta": 0},
                    {"name": "a", "x": 1, "y": 0, "theta": 0},
                ]
            },
            "robots[1].name: 'a' is used twice",
        ),
        (
            {"robots": [{"x": 0, "y": 0, "theta": 0, "profile": "e-puck9"}]},
            "robots[0].profile: unknown robot profile 'e-puck9'; expected one of epuck, "
            "epuck-vrep, e-puck1, e-puck2 or a profile file",
        ),
    ],
)
def test_schema_errors_name_the_field(data, expected):
    with pytest.raises(SceneError) as info:
        scene_from_dict(data, source="bad.toml")
    message = str(info.value)
    assert message.startswith("bad.toml: "), message
    assert expected in message, message


def test_unreadable_and_unknown_scenes_say_what_to_do(tmp_path):
    with pytest.raises(SceneError, match="unknown scene 'nope'; shipped scenes: .*two-robot-pass"):
        load_scene("nope")
    with pytest.raises(SceneError, match="cannot read scene file"):
        load_scene(tmp_path / "missing.toml")
    with pytest.raises(SceneError, match="must end in .toml or .json"):
        load_scene(tmp_path / "scene.yaml")
    with pytest.raises(SceneError, match=r"broken.toml: not valid TOML"):
        parse_scene_text("robots = [", source="broken.toml")
    with pytest.raises(SceneError, match=r"broken.json: not valid JSON"):
        parse_scene_text("{", source="broken.json")


def test_a_robot_starting_outside_the_arena_is_refused_with_the_bounds():
    """x = 5.0 in a 1 m arena is a typo, not a start: the engine would push the robot
    4.5 m back through the wall and the run would go on. One line names the robot and
    the walls."""
    data = minimal(arena={"size": [1.0, 0.8]})
    data["robots"][0].update(name="solo", x=5.0)
    with pytest.raises(SceneError) as info:
        scene_from_dict(data, source="bad.toml")
    assert str(info.value) == (
        "bad.toml: robots[0].x: robot 'solo' starts at (5, 0) m, outside the arena "
        "(x from -0.5 to 0.5 m, y from -0.4 to 0.4 m); give a start inside the walls"
    )
    # placed on the track outside the walls: the placing key is named
    data = {
        "arena": {"size": [0.4, 0.4]},
        "track": {"shape": "circle", "radius": 0.5},
        "robots": [{"name": "far", "track_position": 0.0, "direction": "along"}],
    }
    with pytest.raises(SceneError, match=r"robots\[0\]\.track_position: robot 'far' starts at"):
        scene_from_dict(data, source="bad.toml")
    # inside the walls, touching one: accepted (the engine moves it clear, with a warning)
    data = minimal(arena={"size": [1.0, 0.8]})
    data["robots"][0].update(x=0.49)
    assert scene_from_dict(data).robots[0].x == 0.49


@pytest.mark.parametrize(
    ("data", "expected"),
    [
        (
            {"track": {"shape": "circle", "radius": 0.5},
             "robots": [{"name": "r", "track_distanse": 0.1, "direction": "along"}]},
            "robots[0].track_distanse: unknown key; did you mean 'track_distance'?",
        ),
        (
            {"robots": [{"name": "r", "x": 0, "y": 0, "thetta": 0}]},
            "robots[0].thetta: unknown key; did you mean 'theta'?",
        ),
        (
            minimal(obstacles=[{"shape": "circle", "x": 0.3, "y": 0, "raduis": 0.02}]),
            "obstacles[0].raduis: unknown key; did you mean 'radius'?",
        ),
        (minimal(nosie={"wheel_speed": 0.1}), "nosie: unknown key; did you mean 'noise'?"),
        (
            minimal(track={"shape": "stadium", "lenght": 1, "radius": 0.2}),
            "track.lenght: unknown key; did you mean 'length'?",
        ),
        (minimal(goal={"knd": "avoid"}), "goal.knd: unknown key; did you mean 'kind'?"),
        (minimal(floor_color=[1, 2, 3]), "floor_color: unknown key; did you mean 'floor_colour'?"),
    ],
)  # fmt: skip
def test_an_unknown_key_is_reported_before_what_it_left_missing(data, expected):
    """A typo in a key is the mistake to report, not the required key it left missing
    ("x: missing" for a misspelt track_distance), and the closest known key is named."""
    with pytest.raises(SceneError) as info:
        scene_from_dict(data, source="bad.toml")
    message = str(info.value)
    assert message.startswith(f"bad.toml: {expected}"), message
    assert "known here:" in message and "\n" not in message, message


def test_every_key_of_the_documented_scene_schema_is_accepted():
    """The tables' declared keys (refused first when unknown) cover every key the schema
    on docs/scenarios.md shows, commented-out alternatives included."""
    from pathlib import Path

    page = Path(__file__).resolve().parents[2] / "docs" / "scenarios.md"
    text = page.read_text(encoding="utf-8")
    block = text[text.index('name = "my-scene"') :]
    block = block[: block.index("```")]
    from puckboard.scenario.conversion import (
        ARENA_KEYS,
        CONTROL_KEYS,
        GOAL_KEYS,
        NOISE_KEYS,
        TOP_KEYS,
    )
    from puckboard.scenario.placement import OBSTACLE_KEYS, ROBOT_KEYS
    from puckboard.scenario.tracks import TRACK_KEYS

    tables = {"": TOP_KEYS, "goal": GOAL_KEYS, "track": TRACK_KEYS, "arena": ARENA_KEYS,
              "obstacles": OBSTACLE_KEYS, "robots": ROBOT_KEYS, "noise": NOISE_KEYS,
              "control": CONTROL_KEYS}  # fmt: skip
    table = ""
    for line in block.splitlines():
        header = re.match(r"^\[\[?(\w+)\]\]?", line)
        if header:
            table = header.group(1)
            assert table in TOP_KEYS
            continue
        for key in re.findall(r"^#?\s*(\w+) =", line) + re.findall(r"; (\w+) =", line):
            if key in ("actual", "set", "base"):
                key = "actual" if table == "robots" else key
            assert key in tables[table], (table, key)
