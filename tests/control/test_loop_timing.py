"""The control loop's timing: ``control.period`` (how often the controllers tick) and
``control.latency`` (how long a command takes to reach the wheels), apart from ``dt``.

The default (one tick per step, no delay) must be today's loop exactly; a longer period
ticks less often while the physics keeps stepping; a latency delays each command by
whole physics steps; bad values are refused in one line.
"""

from __future__ import annotations

import dataclasses

import pytest

from puckboard.control.episode import Episode, run_episode
from puckboard.errors import SceneError
from puckboard.scenario import load_scene, scene_from_dict, scene_to_dict
from puckboard.scenario.overrides import apply_scene_overrides
from puckboard.scenario.scene import Control
from puckboard.sim.world import World
from puckboard.sweep.plan import PlanError, parse_set


def without_wall_clock(d):
    return {k: v for k, v in d.items() if k not in ("wall_s", "realtime_factor")}


def test_the_default_timing_set_explicitly_is_todays_loop():
    plain = run_episode("two-robot-pass", seed=3, duration=8.0).to_dict()
    explicit = run_episode(
        "two-robot-pass", seed=3, duration=8.0,
        overrides={"control.period": 0.05, "control.latency": 0},
    ).to_dict()  # fmt: skip
    assert without_wall_clock(plain) == without_wall_clock(explicit)
    assert "control_period_s" not in explicit and "control_latency_s" not in explicit


def test_a_longer_period_ticks_less_often_while_the_physics_steps_at_dt():
    episode = Episode("line-follow", controller="stock", seed=0,
                      overrides={"control.period": 0.15})  # fmt: skip
    ticks = []
    episode.add_observer(lambda e: ticks.append(e.world.step_count))
    result = episode.run(3.0, stop_early=False)
    assert episode.loop.steps_per_cycle == 3
    assert ticks[:3] == [3, 6, 9]  # three physics steps between two ticks
    assert result.steps == 60 and len(ticks) == 20
    d = result.to_dict()
    assert d["control_period_s"] == pytest.approx(0.15) and d["control_latency_s"] == 0.0


def world_with_latency(latency: float) -> World:
    scene = load_scene("line-follow")
    scene = dataclasses.replace(scene, control=Control(latency=latency))
    scene = dataclasses.replace(scene, noise=dataclasses.replace(scene.noise, wheel_speed=0.0))
    return World(scene, seed=1)


def test_a_latency_delays_each_command_by_whole_steps():
    world = world_with_latency(0.1)  # two steps of 0.05 s
    world.drive(0, 2.0, 3.0)
    seen = []
    for _ in range(4):
        world.step()
        seen.append(tuple(world.wheel_speeds[0]))
    # the command given at t = 0 turns the wheels from t = 0.1 s: the third step on
    assert seen == [(0.0, 0.0), (0.0, 0.0), (2.0, 3.0), (2.0, 3.0)]


def test_commands_on_their_way_arrive_in_order_and_a_stop_cancels_them():
    world = world_with_latency(0.1)
    world.drive(0, 1.0, 1.0)
    world.step()
    world.drive(0, 2.0, 2.0)  # given one step later, arrives one step later
    speeds = []
    for _ in range(3):
        world.step()
        speeds.append(world.wheel_speeds[0][0])
    assert speeds == [0.0, 1.0, 2.0]
    world.drive(0, 5.0, 5.0)
    world.stop()
    for _ in range(3):
        world.step()
    assert world.wheel_speeds[0][0] == 0.0


def test_latency_changes_a_run_and_is_reported():
    plain = run_episode("two-robot-pass", seed=3, duration=6.0).to_dict()
    late = run_episode("two-robot-pass", seed=3, duration=6.0,
                       overrides={"control.latency": 0.1}).to_dict()  # fmt: skip
    assert late["control_period_s"] == pytest.approx(0.05)
    assert late["control_latency_s"] == pytest.approx(0.1)
    assert late["steps"] == plain["steps"]
    assert [r["distance_m"] for r in late["robots"]] != [r["distance_m"] for r in plain["robots"]]


@pytest.mark.parametrize(
    ("overrides", "message"),
    [
        (
            {"control.period": 0.07},
            r"control\.period = 0\.07 s is not a whole number of physics steps of dt = 0\.05 s"
            r".*use 0\.05 or 0\.1 s",
        ),
        (
            {"control.latency": 0.03},
            r"control\.latency = 0\.03 s is not a whole number.*use 0 or 0\.05 s",
        ),
        # one bound and one wording for every timing, whatever was wrong with it
        ({"control.period": -0.1}, r"^override control\.period = -0\.1: outside \(0, 1\] s \("),
        ({"control.period": 0}, r"^override control\.period = 0: outside \(0, 1\] s \("),
        (
            {"control.latency": float("nan")},
            r"^override control\.latency = nan: outside \[0, 1\] s",
        ),
        (
            {"control.latency": float("inf")},
            r"^override control\.latency = inf: outside \[0, 1\] s",
        ),
        ({"control.latency": 1e9}, r"^override control\.latency = 1e\+09: outside \[0, 1\] s"),
        ({"dt": 5}, r"^override dt = 5: outside \(0, 1\] s \(simulation step\)"),
        (
            {"control.period": "fast"},
            r"^override control\.period = 'fast': expected a number \(seconds, or",
        ),
        (
            {"control.period": "50mm"},
            r"^override control\.period = '50mm': unit 'mm' does not fit; seconds",
        ),
        ({"dt": 0.02, "control.period": 0.05}, r"control\.period = 0\.05 s .* dt = 0\.02 s"),
        ({"control.period": 0.5}, r"control\.period 0\.5 s is longer than the robots' control"),
    ],
)
def test_bad_timing_is_refused_in_one_line(overrides, message):
    with pytest.raises(ValueError, match=message) as info:
        apply_scene_overrides(load_scene("two-robot-pass"), overrides)
    assert "\n" not in str(info.value)


def test_a_timing_may_carry_its_unit_as_every_setting_may():
    scene = apply_scene_overrides(
        load_scene("two-robot-pass"), {"control.period": "100ms", "control.latency": "50ms"}
    )
    assert scene.control == Control(period=0.1, latency=0.05)


def test_a_scene_built_in_python_is_bounded_where_an_episode_reads_it():
    """No hang and no memory eaten: a latency of 1e9 s built into a scene by hand is one
    line before the world (and its delay line) is built."""
    scene = dataclasses.replace(load_scene("line-follow"), control=Control(latency=1e9))
    with pytest.raises(SceneError, match=r"^scene 'line-follow': control\.latency = 1e\+09: out"):
        Episode(scene, controller="stock")


def test_a_period_follows_a_changed_dt():
    scene = apply_scene_overrides(
        load_scene("two-robot-pass"), {"dt": 0.025, "control.period": 0.1, "control.latency": 0.05}
    )
    assert scene.control.steps(scene.dt) == (4, 2)


def minimal(**extra):
    data = {"robots": [{"name": "r", "x": 0.0, "y": 0.0, "theta": 0.0}]}
    data.update(extra)
    return data


def test_a_scene_file_sets_the_timing_and_keeps_it_through_its_dict():
    scene = scene_from_dict(minimal(control={"period": 0.1, "latency": 0.05}))
    assert scene.control == Control(period=0.1, latency=0.05)
    again = scene_from_dict(scene_to_dict(scene))
    assert again.control == scene.control
    assert "control" not in scene_to_dict(scene_from_dict(minimal()))  # default: as before


@pytest.mark.parametrize(
    ("control", "message"),
    [
        ({"period": 0.07}, r"^s\.toml: control\.period = 0\.07 s is not a whole number"),
        ({"latency": -1}, r"^s\.toml: control\.latency: expected a number >= 0 \(s\), got -1"),
        ({"period": 0}, r"^s\.toml: control\.period: expected a number > 0 \(s\)"),
        ({"perod": 0.1}, r"^s\.toml: control\.perod: unknown key; did you mean 'period'"),
    ],
)
def test_a_scene_files_bad_timing_names_the_file_and_field(control, message):
    with pytest.raises(SceneError, match=message):
        scene_from_dict(minimal(control=control), source="s.toml")


def test_sweeps_and_tuning_accept_the_timing_as_parameters():
    assert parse_set("control.period=0.05,0.1") == ("control.period", (0.05, 0.1))
    assert parse_set("control.latency=0,0.05")[1] == (0, 0.05)
    with pytest.raises(PlanError, match=r"control.latency = -0.05: outside \[0, 1\] s"):
        parse_set("control.latency=-0.05")
    with pytest.raises(PlanError, match=r"control.period = 0: outside \(0, 1\] s"):
        parse_set("control.period=0")
    with pytest.raises(PlanError, match=r"control.latency = 1e\+09: outside \[0, 1\] s"):
        parse_set("control.latency=0.05,1e9")


def test_a_latency_is_refused_where_no_simulator_can_delay_the_commands():
    with pytest.raises(
        SceneError, match=r"control\.latency = 0\.05 s is simulated by the embedded backend only"
    ):
        Episode("line-follow", controller="stock", backend="fake",
                overrides={"control.latency": 0.05})  # fmt: skip


def one_error_line(capsys, command: str) -> str:
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1, lines
    assert lines[0].startswith(f"puckboard {command}: error: ")
    return lines[0]


@pytest.mark.parametrize("command", ["run", "sweep", "sensitivity"])
def test_every_command_refuses_a_period_off_the_step_in_one_line(capsys, command):
    from puckboard.cli import main

    args = [command, "line-follow", "--set", "control.period=0.07", "--duration", "1"]
    if command == "sweep":
        args += ["--seeds", "0:1"]
    assert main(args) == 2
    assert "control.period = 0.07 s is not a whole number" in one_error_line(capsys, command)


def test_sensitivity_runs_every_point_at_the_fixed_timing(capsys):
    import json

    from puckboard.cli import main

    args = ["sensitivity", "line-follow", "--controller", "stock", "--profile", "epuck",
            "--fields", "axle_length", "--values", "2", "--seeds", "0:1", "--duration", "1",
            "--set", "control.period=0.1", "--workers", "1", "--json", "--quiet"]  # fmt: skip
    assert main(args) == 0
    fixed = json.loads(capsys.readouterr().out)["fixed"]
    assert fixed == {"duration": 1.0, "control.period": 0.1}
    assert main([*args[:-2], "--set", "profile.axle_length=0.05"]) == 2
    assert "the robots are --profile's" in one_error_line(capsys, "sensitivity")
