"""An episode refuses a run it could never finish: too many steps, or no finite end."""

from __future__ import annotations

import math

import pytest

from puckboard.control import episode as episode_module
from puckboard.control.episode import MAX_STEPS, Episode, check_steps


def test_check_steps_counts_and_names_the_limit():
    assert check_steps(1.0, 0.05) == 20
    with pytest.raises(ValueError, match="MAX_STEPS") as info:
        check_steps(1.0, 1e-9)
    text = str(info.value)
    assert f"{MAX_STEPS:,}" in text and "dt=1e-09" in text and "1 s" in text
    assert "larger dt or a shorter duration" in text


def test_episode_refuses_too_many_steps_before_running(monkeypatch):
    episode = Episode("line-follow", backend="embedded", overrides={"dt": 1e-6})
    try:
        with pytest.raises(ValueError, match="MAX_STEPS"):
            episode.run(60.0)  # 6e7 steps
        assert episode.loop.cycles == 0
        monkeypatch.setattr(episode_module, "MAX_STEPS", 10)
        with pytest.raises(ValueError, match=r"100 steps, more than one episode may take \(10,"):
            episode.check_duration(1e-4)  # 100 steps of 1 µs
    finally:
        episode.connection.close()


@pytest.mark.parametrize("duration", [math.inf, math.nan, 0.0, -1.0])
def test_episode_duration_must_be_finite_and_positive(duration):
    episode = Episode("line-follow", backend="embedded")
    try:
        with pytest.raises(ValueError, match="finite positive number of seconds"):
            episode.run(duration)
    finally:
        episode.connection.close()
