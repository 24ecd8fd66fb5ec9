"""The scene a run plays: one pipeline of named steps, each condition drawn once."""

from __future__ import annotations

import pytest

from puckboard.control.episode import Episode
from puckboard.scenario import reality_gap
from puckboard.scenario.preparation import STEPS, RunRequest, prepare_scene
from puckboard.scenario.scenefile import load_scene


def _episode(**kwargs):
    episode = Episode("two-robot-pass", **kwargs)
    episode.connection.close()
    return episode


def test_the_steps_are_named_in_the_order_a_run_takes_them():
    assert [step.__name__ for step in STEPS] == [
        "draw_track", "apply_settings", "draw_variation", "take_link_timing"
    ]  # fmt: skip


def test_reality_gaps_conditions_are_drawn_once_and_reported_as_played(monkeypatch):
    drawn = []
    uniform = reality_gap._uniform

    def counted(rng, name):
        drawn.append(name)
        return uniform(rng, name)

    monkeypatch.setattr(reality_gap, "_uniform", counted)
    episode = _episode(seed=3, variation="reality-gap", overrides={"noise.ground": 0.02})
    assert drawn.count("noise.proximity") == 1  # one drawing, played and reported
    played, reported = episode.scene, episode.conditions
    assert played.noise.proximity == reported["noise.proximity"]
    assert played.noise.ground == 0.02 and "noise.ground" not in reported  # set by the run
    assert played.control.period == reported["control.period"]


def test_an_episode_plays_the_scene_the_pipeline_prepares():
    scene = load_scene("two-robot-pass")
    run = RunRequest(4, {"noise.proximity": 0.01}, "plausible", simulates_link=True)
    prepared = prepare_scene(scene, run)
    episode = _episode(seed=4, variation="plausible", overrides={"noise.proximity": 0.01})
    played = episode.scene
    assert (played.robots, played.noise, played.control) == (
        prepared.scene.robots, prepared.scene.noise, prepared.scene.control
    )  # fmt: skip
    assert prepared.conditions is None
    assert [r.actual for r in prepared.scene.robots] != [None, None]


def test_an_unknown_variation_is_refused_before_a_backend_opens():
    with pytest.raises(ValueError, match="unknown variation 'wild'"):
        prepare_scene(load_scene("two-robot-pass"), RunRequest(0, {}, "wild"))
