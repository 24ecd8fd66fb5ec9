"""Ctrl-C during a recorded run: say what is kept and what is being written, and let a
second Ctrl-C abandon a long animation without leaving the robots open."""

from __future__ import annotations

import logging

import pytest

from puckboard.control.episode import Episode
from puckboard.viz import animation
from puckboard.viz.hooks import attach


def interrupt_at(cycle):
    def observer(episode):
        if episode.loop.cycles == cycle:
            raise KeyboardInterrupt

    return observer


def test_ctrl_c_with_an_npz_recording_says_it_was_kept_and_where(tmp_path, caplog):
    episode = Episode("line-follow", seed=0)
    path = tmp_path / "run.npz"
    attach(episode, record=path)
    episode.add_observer(interrupt_at(10))
    with caplog.at_level(logging.WARNING), pytest.raises(KeyboardInterrupt):
        episode.run(5.0)
    assert path.is_file()
    assert any("kept in" in r.getMessage() and str(path) in r.getMessage() for r in caplog.records)


def test_a_second_ctrl_c_abandons_the_animation_and_still_closes_the_robots(
    tmp_path, caplog, monkeypatch
):
    def slow_render(rec, path, **kwargs):
        path.write_bytes(b"GIF89a half")  # what a half-written animation leaves
        raise KeyboardInterrupt  # the user presses Ctrl-C again

    monkeypatch.setattr(animation, "render_animation", slow_render)
    episode = Episode("line-follow", seed=0)
    gif = tmp_path / "run.gif"
    attach(episode, record=gif)
    episode.add_observer(interrupt_at(10))
    with caplog.at_level(logging.WARNING), pytest.raises(KeyboardInterrupt):
        episode.run(5.0)
    messages = [r.getMessage() for r in caplog.records]
    assert any("writing the animation" in m and "Ctrl-C again" in m for m in messages)
    assert any("abandoned" in m for m in messages)
    assert not gif.exists()
    assert all(adapter.closed for adapter in episode.connection.adapters.values())
