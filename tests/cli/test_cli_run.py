"""``puckboard run`` and ``puckboard scenes`` as users and scripts call them."""

from __future__ import annotations

import json

import pytest

from puckboard.cli import main
from puckboard.cli.run import realtime_text


def test_json_prints_exactly_one_object_on_stdout(capsys):
    code = main(
        ["run", "line-follow", "--controller", "stock", "--seed", "2", "--duration", "3", "--json"]
    )
    out = capsys.readouterr().out
    assert code == 0
    assert out.endswith("\n") and out.count("\n") == 1
    d = json.loads(out)
    assert d["scenario"] == "line-follow" and d["controller"] == "stock" and d["seed"] == 2
    assert d["sim_time_s"] == 3.0 and d["failure"] == "timeout" and d["success"] is False
    assert [r["name"] for r in d["robots"]] == ["epuck"]


def test_default_run_is_the_two_robot_pass_with_the_improved_controller(capsys):
    code = main(["run", "--duration", "2", "--json"])
    d = json.loads(capsys.readouterr().out)
    assert code == 0
    assert d["scenario"] == "two-robot-pass" and d["controller"] == "improved"
    assert [r["name"] for r in d["robots"]] == ["left", "right"]


def test_readable_summary_names_the_outcome(capsys):
    assert main(["run", "two-robot-pass", "--duration", "2", "--set", "noise.wheel_speed=0"]) == 0
    out = capsys.readouterr().out
    assert "outcome: FAILED (not_passed" in out
    assert "left" in out and "right" in out and "passed other" in out


def test_a_scene_file_runs(tmp_path, capsys):
    path = tmp_path / "tiny.toml"
    path.write_text(
        '[arena]\nsize = [0.5, 0.5]\n[[robots]]\nname = "solo"\nx = 0\ny = 0\ntheta = 0\n',
        encoding="utf-8",
    )
    assert main(["run", str(path), "--duration", "1", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["scenario"] == "tiny" and d["success"] is True  # avoid goal, nothing touched


def run_error(capsys, args):
    code = main(["run", *args])
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    return code, lines[-1] if lines else ""


def test_bad_input_exits_2_with_one_clear_line(tmp_path, capsys):
    code, line = run_error(capsys, ["no-such-scene"])
    assert code == 2 and "unknown scene 'no-such-scene'" in line
    code, line = run_error(capsys, [str(tmp_path / "missing.toml")])
    assert code == 2 and "cannot read scene file" in line
    bad = tmp_path / "bad.toml"
    bad.write_text('[[robots]]\nx = 0\ny = 0\ntheta = "north"\n', encoding="utf-8")
    code, line = run_error(capsys, [str(bad)])
    assert code == 2 and "robots[0].theta: expected a number (radians), got 'north'" in line
    code, line = run_error(capsys, ["--controller", "wobbly"])
    assert code == 2 and "unknown controller 'wobbly'" in line
    code, line = run_error(capsys, ["--controller", "no_such_module_x:make"])
    assert code == 2 and "cannot import controller module" in line
    code, line = run_error(capsys, ["--set", "noise.wheel_speed"])
    assert code == 2 and "expected NAME=VALUE" in line
    code, line = run_error(capsys, ["--set", "layer.Nope.speed=1"])
    assert code == 2 and "no controller has a layer 'Nope'" in line
    code, line = run_error(capsys, ["--json", "--monitor"])
    assert code == 2 and "--monitor" in line
    code, line = run_error(capsys, ["--host", "10.0.0.2"])
    assert code == 2 and "--host" in line


def test_scenes_lists_and_shows(capsys):
    assert main(["scenes"]) == 0
    out = capsys.readouterr().out
    for name in ("two-robot-pass", "line-follow", "arena"):
        assert name in out
    assert main(["scenes", "show", "two-robot-pass"]) == 0
    assert 'name = "two-robot-pass"' in capsys.readouterr().out
    assert main(["scenes", "show", "nope"]) == 2


def test_a_start_outside_the_arena_stops_the_run_with_one_line(tmp_path, capsys):
    """Before: the robot was moved 4.5 m back with a warning and the run said SUCCESS."""
    path = tmp_path / "outside.toml"
    path.write_text(
        '[arena]\nsize = [1.0, 1.0]\n[[robots]]\nname = "solo"\nx = 5.0\ny = 0\ntheta = 0\n',
        encoding="utf-8",
    )
    code = main(["run", str(path), "--duration", "1"])
    captured = capsys.readouterr()
    assert code == 2 and captured.out == ""
    (line,) = captured.err.strip().splitlines()
    assert "outside.toml: robots[0].x: robot 'solo' starts at (5, 0) m, outside the arena" in line
    assert "(x from -0.5 to 0.5 m, y from -0.5 to 0.5 m)" in line


@pytest.mark.parametrize(
    ("factor", "shown"),
    [(185.3, "185x"), (12.4, "12x"), (1.94, "1.9x"), (0.1234, "0.12x"), (0.0123, "0.012x")],
)
def test_the_real_time_factor_keeps_two_significant_figures(factor, shown):
    """The run's header writes its real-time factor with two significant figures
    (issue 30, round 4, item 10)."""
    assert realtime_text(factor) == shown
