"""Every example runs headless for a short simulated time and does what its docstring
promises: the outcome is checked, not only the absence of a crash."""

from __future__ import annotations

import importlib.util
import inspect
import os
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
NAMES = (
    "control_loop",
    "layered",
    "task_control",
    "subsumption",
    "blackboard",
    "first_layer",
    "compose_controller",
    "switch_backend",
)


def load(name: str) -> ModuleType:
    spec = importlib.util.spec_from_file_location(
        f"puckboard_example_{name}", EXAMPLES / f"{name}.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up while being built
    spec.loader.exec_module(module)
    return module


# -- every example has the same shape -----------------------------------------------------
def test_every_teaching_example_is_in_the_examples_folder() -> None:
    found = {p.stem for p in EXAMPLES.glob("*.py")}
    assert set(NAMES) <= found, sorted(set(NAMES) - found)


@pytest.mark.parametrize("name", NAMES)
def test_example_explains_itself_and_has_a_checkable_main(name: str) -> None:
    module = load(name)
    doc = module.__doc__ or ""
    assert len(doc.splitlines()) >= 8, f"{name}: the docstring should explain the idea"
    assert "What to watch" in doc, f"{name}: say what to watch"
    assert f"python examples/{name}.py" in doc, f"{name}: say how to run it"
    params = inspect.signature(module.main).parameters
    assert params["duration"].default > 0
    assert params["seed"].default == 0
    source = (EXAMPLES / f"{name}.py").read_text(encoding="utf-8")
    assert 'if __name__ == "__main__":' in source


# -- outcomes -----------------------------------------------------------------------------
def test_control_loop_stays_on_the_line() -> None:
    out = load("control_loop").main(duration=20.0)
    assert out["sim_time_s"] == pytest.approx(20.0, abs=0.06)
    assert out["on_line_fraction"] > 0.9
    assert out["distance_m"] > 0.5  # ~4 cm/s for 20 s: it really drove


def test_control_loop_is_reproducible_with_a_seed() -> None:
    example = load("control_loop")
    assert example.main(duration=5.0, seed=3) == example.main(duration=5.0, seed=3)


def test_layered_levels_hand_results_up_and_follow_the_line() -> None:
    example = load("layered")
    out = example.main(duration=20.0)
    assert out["on_line_fraction"] > 0.9
    assert out["intents"].get("follow", 0) > 0
    assert sum(out["intents"].values()) == 400  # one decision per 0.05 s cycle
    # each level works alone, as the docstring claims
    interpret, decide = example.SensorInterpretation(), example.Decision()
    from puckboard.records import Ground

    left_dark = Ground([0.1, 0.9, 0.9], [100, 900, 900])
    position = interpret(left_dark)
    assert position is not None and position > 0  # the line is to the left
    assert decide(position).kind == "follow"
    assert decide(None) == example.Intent("search", 0.8)  # search on the side last seen
    command = example.Actuation()(example.Intent("follow", 1.0))
    assert command.right > command.left


def test_task_control_finishes_its_tasks_in_order_then_stops() -> None:
    out = load("task_control").main(duration=45.0)
    times = list(out["finished"].values())
    assert list(out["finished"]) == [
        "follow the line for 1 m",
        "turn around",
        "follow the line for 0.5 m",
    ]
    assert all(t is not None for t in times), out["finished"]
    assert times == sorted(times)
    assert out["final_layer"] == "Stop"
    # 1 m + 0.5 m along the line, plus the wheels' arc while turning on the spot
    assert 1.5 <= out["distance_m"] < 1.8


def test_subsumption_avoidance_takes_control_when_an_obstacle_is_close() -> None:
    out = load("subsumption").main(duration=10.0)
    assert out["close"] > 0, "the robots should meet something within 10 s"
    assert out["avoid_when_close"] == out["close"]
    assert out["held_after"] > 0, "HoldFor should keep the avoidance layer on after the obstacle"
    assert sum(out["layer_share"].values()) == pytest.approx(1.0)
    assert "LineFollow" in out["layer_share"]


def test_subsumption_without_hold_lets_go_as_soon_as_the_obstacle_is_gone() -> None:
    example = load("subsumption")
    example.HOLD = 0.0
    out = example.main(duration=10.0)
    assert out["close"] > 0
    assert out["avoid_when_close"] == out["close"]
    assert out["held_after"] == 0


def test_blackboard_modules_write_derived_keys_stamped_like_their_inputs() -> None:
    out = load("blackboard").main(duration=20.0)
    assert out["derived"]["percept/line_seen"] is True
    assert out["stamps"]["percept/line_position"] == out["stamps"]["ground"]
    assert out["stamps"]["estimate/distance_m"] == out["stamps"]["ground"]
    odometry = out["derived"]["estimate/distance_m"]
    assert odometry == pytest.approx(out["true_distance_m"], rel=0.05)
    assert [round(m, 1) for _, m in out["milestones"]][:1] == [0.5]
    assert [t for t, _ in out["milestones"]] == sorted(t for t, _ in out["milestones"])
    assert out["on_line_fraction"] > 0.9


def test_first_layer_turns_left_when_blocked_and_saves_collisions() -> None:
    out = load("first_layer").main(duration=40.0)
    assert out["by_hand"] == {
        "nothing in front": "Cruise",
        "obstacle 2 cm ahead": "TurnLeftWhenBlocked",
        "turns": "left",
    }
    assert out["collisions_cruise_only"] > 0
    assert out["collisions_with_layer"] < out["collisions_cruise_only"]


def test_compose_controller_orders_layers_by_priority() -> None:
    example = load("compose_controller")
    controller = example.composed(inner_factor=0.3)
    assert [layer.name for layer in controller.layers] == [
        "FrontObstacleLeftTurn",
        "LineFollow",
        "SideWallKeep",
        "Cruise",
    ]
    assert controller.find("LineFollow").inner_factor == 0.3


def test_compose_controller_gets_the_robots_past_each_other_where_stock_collides() -> None:
    out = load("compose_controller").main(duration=40.0)
    stock = out["stock"]
    assert stock.failure == "collision"
    # the touch comes at the meeting: any robot that gets past the other does so after it
    touched = min(e.time_s for e in stock.events if e.kind == "collision")
    assert all(e.time_s > touched for e in stock.events if e.kind == "passed_other")
    composed = out["composed"]
    assert all(r.passed_other for r in composed.robots)
    assert composed.failure not in ("collision", "parallel_driving", "stuck")
    assert sum(r.collisions for r in composed.robots) == 0


def test_switch_backend_runs_embedded_by_default() -> None:
    example = load("switch_backend")
    assert example.BACKEND == "embedded"
    result = example.main(duration=10.0)
    assert result.sim_time_s == pytest.approx(10.0, abs=0.06)
    assert result.robots[0].on_line_fraction > 0.9


def test_switch_backend_documents_only_backends_that_exist() -> None:
    import re

    from puckboard.backends.registry import BACKENDS

    example = load("switch_backend")
    named = set(re.findall(r'BACKEND, OPTIONS = "([\w-]+)"', example.__doc__))
    assert named == {"embedded", "coppeliasim", "epuck2-wifi", "sercom"}
    assert named <= set(BACKENDS)
    with pytest.raises(ValueError, match="unknown backend"):
        example.main(duration=1.0, backend="no-such-backend")


# -- as a student runs them ---------------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("name", ["control_loop", "task_control", "blackboard"])
def test_example_runs_as_a_script_and_prints_its_outcome(name: str) -> None:
    env = dict(os.environ, MPLBACKEND="Agg")
    result = subprocess.run(
        [sys.executable, str(EXAMPLES / f"{name}.py")],
        capture_output=True, text=True, timeout=120, env=env, cwd=EXAMPLES.parent,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr[-2000:]
    assert result.stdout.strip(), "the example should print its outcome"


@pytest.mark.network
def test_switch_backend_coppeliasim_line_drives_a_served_simulation() -> None:
    """The documented CoppeliaSim line, against `puckboard serve` on the loopback: the
    same controller, a different backend, the same outcome."""
    pytest.importorskip("zmq")
    pytest.importorskip("cbor2")
    pytest.importorskip("coppeliasim_zmqremoteapi_client")
    from puckboard.backends.coppeliasim.server.socket_loop import serve_scene

    example = load("switch_backend")
    server = serve_scene("line-follow", host="127.0.0.1", port=0)
    try:
        result = example.main(
            duration=5.0, backend="coppeliasim", options={"host": "127.0.0.1", "port": server.port}
        )
    finally:
        server.close()
    assert result.sim_time_s == pytest.approx(5.0, abs=0.06)
    robot = result.robots[0]
    assert robot.on_line_fraction > 0.9
    assert robot.distance_m > 0.1  # it drove through the remote API


# -- installed with the package -----------------------------------------------------------
def test_examples_are_installed_as_a_package_and_listed_by_the_cli(capsys) -> None:
    import puckboard.examples

    from puckboard.cli import main

    assert Path(puckboard.examples.__file__).resolve().parent == EXAMPLES
    assert main(["examples"]) == 0
    listed = {line.split()[0] for line in capsys.readouterr().out.splitlines()}
    assert listed == {p.stem for p in EXAMPLES.glob("*.py") if not p.stem.startswith("_")}


def test_examples_show_prints_the_source_and_run_runs_it(capsys) -> None:
    from puckboard.cli import main

    assert main(["examples", "show", "first_layer"]) == 0
    assert capsys.readouterr().out == (EXAMPLES / "first_layer.py").read_text(encoding="utf-8")
    assert main(["examples", "run", "go_home", "--duration", "4", "--after", "2"]) == 0
    assert "home" in capsys.readouterr().out.lower()
    assert main(["examples", "run", "nope"]) == 2
    assert "no example 'nope'; examples: blackboard" in capsys.readouterr().err
