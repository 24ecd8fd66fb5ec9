"""Episodes: determinism, overrides, observers, the result contract."""

from __future__ import annotations

import pytest

from puckboard.control.episode import Episode, run_episode

FIELDS = {
    "scenario", "controller", "seed", "dt_s", "steps", "sim_time_s", "wall_s",
    "realtime_factor", "success", "failure", "failures", "robots", "events",
}  # fmt: skip
ROBOT_FIELDS = {
    "name",
    "profile",
    "profile_values",
    "progress_laps",
    "distance_m",
    "collisions",
    "on_line_fraction",
    "obstacles_passed",
    "passed_other",
}


def without_wall_clock(d):
    return {k: v for k, v in d.items() if k not in ("wall_s", "realtime_factor")}


def test_same_seed_same_result_and_other_seed_differs():
    a = run_episode("two-robot-pass", controller="improved", seed=3, duration=12.0).to_dict()
    b = run_episode("two-robot-pass", controller="improved", seed=3, duration=12.0).to_dict()
    c = run_episode("two-robot-pass", controller="improved", seed=4, duration=12.0).to_dict()
    assert without_wall_clock(a) == without_wall_clock(b)
    assert [r["distance_m"] for r in a["robots"]] != [r["distance_m"] for r in c["robots"]]


def test_naming_the_scene_s_own_profile_is_the_same_episode():
    """tests/support/episodes.py keys such an episode as the scene's own, run once."""
    plain = run_episode("two-robot-pass", controller="robust", seed=2, duration=12.0)
    named = run_episode(
        "two-robot-pass", controller="robust", seed=2, duration=12.0,
        overrides={"robot.profile": "epuck-vrep"},
    )  # fmt: skip
    other = run_episode(
        "two-robot-pass", controller="robust", seed=2, duration=12.0,
        overrides={"robot.profile": "epuck"},
    )  # fmt: skip
    assert {r.profile for r in plain.robots} == {"epuck-vrep"}
    assert without_wall_clock(named.to_dict()) == without_wall_clock(plain.to_dict())
    assert without_wall_clock(other.to_dict()) != without_wall_clock(plain.to_dict())


def test_result_dict_has_exactly_the_contract_fields():
    d = run_episode("line-follow", controller="stock", seed=0, duration=5.0).to_dict()
    assert set(d) == FIELDS
    assert d["scenario"] == "line-follow" and d["controller"] == "stock" and d["seed"] == 0
    assert d["dt_s"] == 0.05 and d["steps"] == 100 and d["sim_time_s"] == pytest.approx(5.0)
    assert d["success"] is False and d["failure"] == "timeout"  # 5 s is not 2.5 laps
    assert d["failures"] == ["timeout"]
    for r in d["robots"]:
        assert set(r) == ROBOT_FIELDS
        assert r["progress_laps"] > 0 and r["distance_m"] == pytest.approx(5.0 * 0.043, rel=0.2)
    for e in d["events"]:
        assert set(e) == {"time_s", "robot", "kind"}


def test_overrides_reach_the_scene_and_every_robots_layer():
    ep = Episode(
        "two-robot-pass",
        controller="improved",
        overrides={
            "noise.wheel_speed": 0.1,
            "dt": 0.025,
            "duration": 3.0,
            "layer.SideWallKeep.near_fraction": 0.3,
        },
    )
    try:
        assert ep.scene.noise.wheel_speed == 0.1 and ep.scene.dt == 0.025
        assert ep.scene.duration == 3.0
        assert all(c.find("SideWallKeep").near_fraction == 0.3 for c in ep.controllers.values())
        result = ep.run()
        assert result.sim_time_s == pytest.approx(3.0) and result.steps == 120
    finally:
        ep.connection.close()


@pytest.mark.parametrize(
    ("overrides", "message"),
    [
        ({"noise.wheels": 1.0}, "unknown override 'noise.wheels'"),
        ({"speed": 1.0}, "unknown override 'speed'"),
        ({"dt": -1}, r"override dt = -1: outside \(0, 1\] s"),
        ({"layer.Nope.speed": 1.0}, "no controller has a layer 'Nope'"),
        ({"layer.LineFollow.nope": 1.0}, "has no parameter 'nope'"),
        ({"layer.LineFollow.speed": "fast"}, "needs a number"),
    ],
)
def test_bad_overrides_are_refused_before_anything_runs(overrides, message):
    with pytest.raises(ValueError, match=message):
        Episode("two-robot-pass", overrides=overrides)


def test_observers_see_every_cycle_and_close_once():
    ep = Episode("line-follow", controller="improved", seed=1)
    seen, closed = [], []
    ep.add_observer(lambda e: seen.append(e.time))
    ep.add_close_observer(lambda e: closed.append(e.time))
    result = ep.run(2.0)
    assert len(seen) == result.steps == 40
    assert seen[-1] == pytest.approx(2.0)
    assert closed == [pytest.approx(2.0)]


def test_an_error_in_an_observer_closes_everything():
    ep = Episode("line-follow", controller="improved")
    closed = []
    ep.add_close_observer(lambda e: closed.append(True))

    def boom(e):
        if e.time > 0.5:
            raise RuntimeError("viewer crashed")

    ep.add_observer(boom)
    with pytest.raises(RuntimeError, match="viewer crashed"):
        ep.run(5.0)
    assert closed == [True]
    assert all(a.closed for a in ep.connection.adapters.values())
