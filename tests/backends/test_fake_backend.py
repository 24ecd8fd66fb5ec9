"""The fake robot is a backend like the others, selectable by name or environment."""

from __future__ import annotations

import pytest

from puckboard.backends.fake import FakeAdapter
from puckboard.backends.registry import BACKEND_ENV, default_backend, open_backend
from puckboard.cli import main
from puckboard.control.episode import run_episode
from puckboard.scenario import load_scene


def test_fake_backend_puts_one_fake_robot_at_each_start_pose():
    scene = load_scene("two-robot-pass")
    with open_backend("fake", scene) as conn:
        assert set(conn.adapters) == {r.name for r in scene.robots}
        for spec in scene.robots:
            robot = conn.adapters[spec.name]
            assert isinstance(robot, FakeAdapter)
            assert (robot.x, robot.y, robot.theta) == (spec.x, spec.y, spec.theta)
        assert conn.stepper is not None and conn.stepper.dt == scene.dt


def test_environment_variable_picks_the_default_backend(monkeypatch):
    monkeypatch.delenv(BACKEND_ENV, raising=False)
    assert default_backend() == "embedded"
    monkeypatch.setenv(BACKEND_ENV, "fake")
    assert default_backend() == "fake"
    result = run_episode("line-follow", duration=1.0)
    # the fake robot drives ideal arcs with no world around it: it moves, nothing collides
    assert result.robots[0].distance_m > 0 and result.robots[0].collisions == 0


def test_an_unknown_backend_in_the_environment_is_named_in_the_error(monkeypatch, capsys):
    monkeypatch.setenv(BACKEND_ENV, "simulink")
    with pytest.raises(ValueError, match="PUCKBOARD_BACKEND='simulink' names no backend"):
        default_backend()
    assert main(["run", "line-follow", "--duration", "1"]) == 2
    assert "PUCKBOARD_BACKEND='simulink'" in capsys.readouterr().err


@pytest.mark.parametrize("value", [-1, float("nan"), float("-inf")])
def test_a_distance_no_sensor_can_read_is_refused_naming_the_sensor(value):
    from puckboard.records import PROX_NAMES

    robot = FakeAdapter()
    with pytest.raises(ValueError) as caught:
        robot.set_proximity(front_left=value)
    assert str(caught.value).startswith(
        f"set_proximity(front_left={value!r}): a distance must be a finite number of metres ≥ 0"
    )
    robot.set_proximity(front_left=1.0, right=0.01)  # beyond the range: sees nothing
    robot.sense_all()
    distance = robot.ns.get("proximity").value.distance
    assert distance[PROX_NAMES.index("front_left")] == robot.profile.prox_range
    assert distance[PROX_NAMES.index("right")] == 0.01
    robot.close()
