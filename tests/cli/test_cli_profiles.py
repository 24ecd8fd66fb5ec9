"""The robot from the command line: --set profile.*, --variation, --profile FILE, profiles show."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from puckboard.cli import main
from puckboard.cli.profile_table import path_table_markdown
from puckboard.control.episode import Episode
from puckboard.profile import EPUCK, EPUCK_VREP, draw, load_profile_file, variation_rng
from puckboard.sweep.plan import PlanError, SweepPlan, parse_set

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "my-epuck.toml"


def run_json(capsys, *args: str) -> dict:
    assert main(["run", *args, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def one_error_line(capsys, command: str) -> str:
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1, lines
    assert lines[0].startswith(f"puckboard {command}: error: ")
    return lines[0]


def test_a_set_number_is_in_every_robot_s_report(capsys):
    report = run_json(
        capsys, "two-robot-pass", "--set", "profile.prox_max_distance=0.045", "--duration", "1"
    )
    assert [r["profile"] for r in report["robots"]] == ["epuck-vrep", "epuck-vrep"]
    assert [r["profile_values"]["prox_max_distance"] for r in report["robots"]] == [0.045] * 2


def test_one_robot_s_number_is_set_by_its_name(capsys):
    report = run_json(
        capsys, "arena", "--set", "robot.north.profile.axle_length=55mm", "--duration", "1"
    )
    north, south = report["robots"]
    assert north["profile_values"]["axle_length"] == 0.055
    assert south["profile_values"]["axle_length"] == EPUCK.axle_length


def test_plausible_robots_differ_and_the_same_seed_draws_them_again(capsys):
    args = ("arena", "--variation", "plausible", "--seed", "3", "--duration", "2")
    first, again = run_json(capsys, *args), run_json(capsys, *args)
    one, two = (r["profile_values"] for r in first["robots"])
    assert one != two
    assert [r["profile_values"] for r in again["robots"]] == [one, two]
    assert one["axle_length"] == draw(EPUCK, variation_rng(3, 0)).axle_length


def test_the_episode_puts_the_drawn_truth_beside_the_believed_profile():
    episode = Episode("arena", seed=3, variation="plausible")
    try:
        robots = episode.scene.robots
        assert [r.profile for r in robots] == ["epuck", "epuck"]
        assert [r.actual for r in robots] == [draw(EPUCK, variation_rng(3, i)) for i in (0, 1)]
    finally:
        episode.connection.close()
    plain = Episode("arena", seed=3)
    try:
        assert all(r.actual is None for r in plain.scene.robots)
    finally:
        plain.connection.close()


def test_the_text_report_lists_the_numbers_that_differ(capsys):
    assert main(["run", "arena", "--duration", "1", "--set", "profile.ir_gain.left=0.8"]) == 0
    out = capsys.readouterr().out
    assert "profile values unlike the shipped profile's" in out
    rows = [line.split() for line in out.splitlines() if line.strip().startswith("ir_gain")]
    assert rows == [["ir_gain.left", "0.8", "0.8"]]
    assert main(["run", "arena", "--duration", "1"]) == 0
    assert "profile values" not in capsys.readouterr().out


def test_a_profile_file_runs_under_its_own_name(capsys):
    report = run_json(capsys, "arena", "--profile", str(EXAMPLE), "--duration", "1")
    assert {r["profile"] for r in report["robots"]} == {"my-epuck"}
    assert report["robots"][0]["profile_values"]["ir_gain.right"] == 0.83


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--set", "profile.prox_max_distanse=0.04"], "did you mean prox_max_distance?"),
        (["--set", "profile.axle_length=53"], "profile.axle_length = 53: outside [0.01 m"),
        (["--set", "robot.nobody.profile.axle_length=0.05"], "no robot 'nobody'"),
        (["--profile", "nope.toml"], "cannot read profile file 'nope.toml'"),
        (
            ["--variation", "wild"],
            "--variation: unknown variation 'wild'; use one of none, plausible",
        ),
    ],
)
def test_bad_robot_input_is_one_line(capsys, args, words):
    assert main(["run", "arena", "--duration", "1", *args]) == 2
    line = one_error_line(capsys, "run")
    assert words in line, line


def test_profiles_show_prints_values_ranges_and_sources(capsys):
    assert main(["profiles", "show", "epuck"]) == 0
    out = capsys.readouterr().out
    assert "prox_radius.side        31 mm                 30–33 mm" in out
    assert main(["profiles", "show", "epuck-vrep", "--markdown"]) == 0
    assert capsys.readouterr().out.strip() == path_table_markdown(EPUCK_VREP)
    assert main(["profiles", "show", "epuck", "--json"]) == 0
    rows = {r["path"]: r for r in json.loads(capsys.readouterr().out)["paths"]}
    right = rows["prox_heading.front_right"]
    assert right["value"] < 0 and right["low"] < right["high"] < 0  # mirrored
    assert rows["ir_gain.left"]["kind"] == "per robot"
    assert "set_source" not in rows["axle_length"]


def test_profiles_show_puts_a_file_beside_its_base(capsys):
    assert main(["profiles", "show", str(EXAMPLE), "--json"]) == 0
    shown = json.loads(capsys.readouterr().out)
    assert shown["name"] == "my-epuck" and shown["base"] == "epuck"
    rows = {r["path"]: r for r in shown["paths"]}
    assert (rows["ir_gain.right"]["value"], rows["ir_gain.right"]["base_value"]) == (0.83, 1.0)
    assert rows["prox_max_distance"]["set_source"] == "a white wall stops registering at 4.5 cm"
    assert [s["path"] for s in shown["set"]] == [p for p, _ in load_profile_file(EXAMPLE).overrides]
    assert main(["profiles", "show", str(EXAMPLE)]) == 0
    assert "(epuck: 50 mm)" in capsys.readouterr().out


def test_the_docs_hold_the_ranges_tables_of_the_code():
    doc = (ROOT / "docs" / "profiles.md").read_text(encoding="utf-8")
    assert path_table_markdown(EPUCK) in doc
    assert path_table_markdown(EPUCK_VREP) in doc


def test_sweeps_take_profile_numbers_in_si_and_a_variation():
    assert parse_set("profile.prox_radius.side=30mm,33mm") == (
        "profile.prox_radius.side",
        (0.03, 0.033),
    )
    with pytest.raises(PlanError, match="did you mean prox_radius.side"):
        parse_set("profile.prox_radius.sid=0.03")
    with pytest.raises(PlanError, match="outside"):
        parse_set("profile.ir_gain=0,1")
    plan = SweepPlan("arena", fixed={"variation": "plausible"}, seeds=range(2))
    assert all(dict(e.params)["variation"] == "plausible" for e in plan.episodes())
    with pytest.raises(PlanError, match="unknown variation 'some'; use one of none, plausible"):
        SweepPlan("arena", fixed={"variation": "some"})


def test_a_sweep_runs_a_profile_file_as_its_base_and_its_numbers(capsys, tmp_path):
    out = tmp_path / "rows.csv"
    code = main(
        ["sweep", "arena", "--seeds", "0:1", "--duration", "1", "--workers", "1", "-q",
         "--profile", str(EXAMPLE), "--variation", "plausible", "--out", str(out)]
    )  # fmt: skip
    assert code == 0
    capsys.readouterr()
    import csv

    (row,) = list(csv.DictReader(out.open(encoding="utf-8")))
    params = json.loads(row["params"])
    assert params["robot.profile"] == "epuck" and params["profile.ir_gain.right"] == 0.83
    assert params["variation"] == "plausible"
    values = json.loads(row["robot.north.profile_values"])
    assert values["ir_gain.right"] == 0.83  # set by the file: not drawn
    assert values["axle_length"] != EPUCK.axle_length  # drawn
    assert row["robot.north.profile"] == "epuck"


def test_serve_gives_its_robots_the_profile_and_the_variation_asked_for():
    import argparse

    from puckboard.cli.serve import served_scene

    def args(**given):
        base = {"scenario": "two-robot-pass", "profile": "epuck-vrep", "seed": 3}
        return argparse.Namespace(**{**base, "variation": "none", **given})

    plain = served_scene(args())
    assert [(r.profile, r.actual) for r in plain.robots] == [("epuck-vrep", None)] * 2
    varied = served_scene(args(profile=str(EXAMPLE), variation="plausible"))
    mine = load_profile_file(EXAMPLE)
    assert [r.profile for r in varied.robots] == [mine, mine]
    assert [r.actual for r in varied.robots] == [draw(mine, variation_rng(3, i)) for i in (0, 1)]


def test_the_emulator_stands_in_for_your_own_e_puck():
    from puckboard.control.emulation import Emulation

    em = Emulation("line-follow", protocol="wifi", profile=str(EXAMPLE))
    try:
        assert em.scene.robots[0].profile == load_profile_file(EXAMPLE)
        assert em.world.profiles[0].prox_max_distance == 0.045
    finally:
        em.close()
