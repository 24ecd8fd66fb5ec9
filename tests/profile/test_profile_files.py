"""Profile files: your own e-puck as a file, checked on load, named by scenes, kept by
recordings."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from puckboard.errors import ProfileError, SceneError
from puckboard.profile import EPUCK, load_profile_file, profile_to_data, resolve_profile
from puckboard.scenario import load_scene, scene_from_dict, scene_to_dict

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "my-epuck.toml"


def write(tmp_path: Path, text: str, name: str = "my-epuck.toml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_the_documented_example_is_the_shipped_file_and_loads():
    doc = (ROOT / "docs" / "profiles.md").read_text(encoding="utf-8")
    block = re.search(r"```toml\n(.*?)```", doc, flags=re.S)
    assert block is not None and block.group(1) == EXAMPLE.read_text(encoding="utf-8")
    mine = load_profile_file(EXAMPLE)
    assert mine.name == "my-epuck" and mine.base == "epuck"
    assert mine.prox_max_distance == 0.045 and mine.wheel_radius == 0.0203
    assert mine.ir_gain[2] == 0.83 and mine.ir_offset[2] == 4.0  # ps2, the right side
    assert mine.sources["prox_max_distance"] == "a white wall stops registering at 4.5 cm"
    assert mine.sources["ir_gain.right"] == "measured on my robot, 2026-11-24"


def test_sub_tables_name_paths_too_and_the_name_defaults_to_the_file_s(tmp_path):
    path = write(tmp_path, 'base = "e-puck2"\n[set.ir_gain]\nright = 0.9\nside = 1.1\n')
    mine = load_profile_file(path)
    assert mine.name == "my-epuck" and mine.base == "epuck"
    assert mine.ir_gain[2] == 0.9 and mine.ir_gain[5] == 1.1  # the sensor wins over its pair


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ('base = "epuck"\n[set]\nprox_max_distance = \n', "my-epuck.toml:3:21: Invalid value"),
        ('bsae = "epuck"\n', "unknown key 'bsae'; known: base, name, source, set"),
        ("[set]\naxle_length = 0.05\n", "base: missing"),
        ('base = "epuk"\n', "base = 'epuk': unknown robot profile; shipped: epuck, epuck-vrep"),
        ('base = "epuck"\n[set]\nprox_max_distanse = 0.04\n', "did you mean prox_max_distance?"),
        (
            'base = "epuck"\n[set]\naxle_length = "wide"\n',
            "axle_length = 'wide': expected a number",
        ),
        ('base = "epuck"\n[set]\naxle_length = 0.5\n', "axle_length = 0.5: outside [0.01 m"),
        ('base = "epuck"\n[set]\naxle_length = { value = 0.05, sauce = "x" }\n', "'sauce'"),
        ('base = "epuck"\nname = "epuck-vrep"\n', "is a shipped profile's"),
    ],
)
def test_a_broken_file_is_one_line_naming_the_file_and_what_is_wrong(tmp_path, text, words):
    with pytest.raises(ProfileError) as info:
        load_profile_file(write(tmp_path, text))
    message = str(info.value)
    assert words in message, message
    assert "my-epuck.toml" in message and len(message.splitlines()) == 1


def test_a_missing_file_says_so(tmp_path):
    with pytest.raises(ProfileError, match="cannot read profile file"):
        resolve_profile(str(tmp_path / "nope.toml"))


def test_a_scene_names_a_profile_file_relative_to_itself(tmp_path):
    (tmp_path / "robots").mkdir()
    write(tmp_path / "robots", 'base = "epuck"\n[set]\naxle_length = 0.055\n')
    scene_file = tmp_path / "scene.toml"
    scene_file.write_text(
        'profile = "robots/my-epuck.toml"\n'
        '[[robots]]\nname = "a"\nx = 0\ny = 0\ntheta = 0\n'
        '[[robots]]\nname = "b"\nx = 0.2\ny = 0\ntheta = 0\nprofile = "epuck-vrep"\n',
        encoding="utf-8",
    )
    scene = load_scene(scene_file)
    a, b = scene.robots
    assert a.profile.name == "my-epuck" and a.profile.axle_length == 0.055
    assert b.profile == "epuck-vrep"


def test_a_scene_naming_a_broken_profile_names_both_files(tmp_path):
    write(tmp_path, 'base = "epuck"\n[set]\naxle_length = 9\n')
    scene_file = tmp_path / "scene.toml"
    scene_file.write_text(
        '[[robots]]\nx = 0\ny = 0\ntheta = 0\nprofile = "my-epuck.toml"\n', encoding="utf-8"
    )
    with pytest.raises(SceneError) as info:
        load_scene(scene_file)
    message = str(info.value)
    assert message.startswith(f"{scene_file}: robots[0].profile: ")
    assert "my-epuck.toml: [set] axle_length = 9: outside" in message


def test_scenes_and_recordings_store_a_changed_robot_inline_and_rebuild_it(tmp_path):
    mine = load_profile_file(EXAMPLE)
    scene = scene_from_dict(
        {"robots": [{"x": 0, "y": 0, "theta": 0, "profile": "epuck"}]}
    ).with_profile(mine)
    stored = json.loads(json.dumps(scene_to_dict(scene)))
    entry = stored["robots"][0]["profile"]
    assert entry["base"] == "epuck" and entry["name"] == "my-epuck"
    assert entry["set"]["prox_max_distance"] == {
        "value": 0.045,
        "source": "a white wall stops registering at 4.5 cm",
    }
    again = scene_from_dict(stored, source="recording")
    assert again.robots[0].profile == mine
    assert scene_to_dict(again) == stored
    # a shipped profile stays a name, as before
    assert scene_to_dict(scene.with_profile("epuck"))["robots"][0]["profile"] == "epuck"
    assert profile_to_data(EPUCK) == "epuck"


def test_a_robot_s_truth_is_stored_beside_its_belief():
    data = {
        "robots": [
            {
                "x": 0, "y": 0, "theta": 0, "profile": "epuck",
                "actual": {"base": "epuck", "set": {"axle_length": 0.055}},
            }
        ]
    }  # fmt: skip
    robot = scene_from_dict(data).robots[0]
    assert robot.profile == "epuck" and robot.actual is not None
    assert robot.actual.axle_length == 0.055
    assert scene_to_dict(scene_from_dict(data))["robots"][0]["actual"]["set"] == {
        "axle_length": 0.055
    }
