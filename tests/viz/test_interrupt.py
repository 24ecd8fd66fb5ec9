"""Ctrl-C during a recorded run: say what is kept and what is being written, and let a
second Ctrl-C abandon a long animation without leaving the robots open."""

from __future__ import annotations

import logging
import signal
from pathlib import Path

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


def press_ctrl_c() -> None:
    """What the terminal does on Ctrl-C: SIGINT to this (the main) thread."""
    signal.raise_signal(signal.SIGINT)


def test_one_ctrl_c_while_the_animation_of_a_finished_run_is_written_keeps_it(
    tmp_path, caplog, monkeypatch
):
    def render_with_one_ctrl_c(rec, path, **kwargs):
        press_ctrl_c()  # the user presses Ctrl-C once while frames are encoded
        path.write_bytes(b"GIF89a whole")
        return {"path": path}

    monkeypatch.setattr(animation, "render_animation", render_with_one_ctrl_c)
    episode = Episode("line-follow", seed=0)
    gif = tmp_path / "run.gif"
    attach(episode, record=gif)
    handler = signal.getsignal(signal.SIGINT)
    with caplog.at_level(logging.WARNING), pytest.raises(KeyboardInterrupt):
        episode.run(1.0)  # the run completes; the Ctrl-C came after it
    messages = [r.getMessage() for r in caplog.records]
    assert any("Ctrl-C again" in m and "abandon" in m and str(gif) in m for m in messages)
    assert gif.read_bytes() == b"GIF89a whole"  # the first Ctrl-C did not throw it away
    assert signal.getsignal(signal.SIGINT) is handler  # Ctrl-C is itself again
    assert all(adapter.closed for adapter in episode.connection.adapters.values())


def test_two_ctrl_c_while_the_animation_of_a_finished_run_is_written_abandon_it(
    tmp_path, caplog, monkeypatch
):
    def render_with_two_ctrl_c(rec, path, **kwargs):
        path.write_bytes(b"GIF89a half")
        press_ctrl_c()
        press_ctrl_c()  # raises here: the second press abandons the animation
        raise AssertionError("the second Ctrl-C did not interrupt")

    monkeypatch.setattr(animation, "render_animation", render_with_two_ctrl_c)
    episode = Episode("line-follow", seed=0)
    gif = tmp_path / "run.gif"
    attach(episode, record=gif)
    with caplog.at_level(logging.WARNING), pytest.raises(KeyboardInterrupt):
        episode.run(1.0)
    assert any("abandoned" in r.getMessage() for r in caplog.records)
    assert not gif.exists()


def test_ctrl_c_while_the_gif_is_written_ends_the_command_with_status_130(
    tmp_path, capsys, caplog, monkeypatch
):
    from puckboard.cli import main

    def render_with_one_ctrl_c(rec, path, **kwargs):
        press_ctrl_c()
        path.write_bytes(b"GIF89a whole")
        return {"path": path}

    monkeypatch.setattr(animation, "render_animation", render_with_one_ctrl_c)
    gif = tmp_path / "run.gif"
    with caplog.at_level(logging.WARNING):
        assert main(["run", "line-follow", "--duration", "1", "--record", str(gif)]) == 130
    err = capsys.readouterr().err
    assert "Traceback" not in err and err.rstrip().endswith("puckboard run: interrupted")
    assert "Ctrl-C again" in caplog.text
    assert gif.is_file()


def test_an_animation_abandoned_while_it_is_saved_leaves_no_part_file(tmp_path, monkeypatch):
    pytest.importorskip("PIL")
    from PIL import Image

    from puckboard.recording.recorder import Recorder

    episode = Episode("line-follow", seed=0)
    recorder = Recorder.for_episode(episode, None)
    episode.add_observer(recorder)
    episode.run(1.0)
    rec = recorder.close()

    def save_half_then_ctrl_c(self, fp, *args, **kwargs):
        Path(fp).write_bytes(b"GIF89a half")
        raise KeyboardInterrupt

    monkeypatch.setattr(Image.Image, "save", save_half_then_ctrl_c)
    gif = tmp_path / "run.gif"
    with pytest.raises(KeyboardInterrupt):
        animation.render_animation(rec, gif)
    assert list(tmp_path.iterdir()) == []
