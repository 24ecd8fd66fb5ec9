import matplotlib.pyplot as plt
import numpy as np
import pytest
from PIL import Image

from puckboard.control.episode import Episode
from puckboard.recording.recorder import load_recording
from puckboard.viz.hooks import attach
from puckboard.viz.live import LiveView


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _run(tmp_path, tag, *, view, seconds=3.0):
    ep = Episode("two-robot-pass", controller="improved", seed=0)
    outputs = attach(ep, record=tmp_path / f"{tag}.npz")
    if view:  # headless stand-in for the window: the same view, drawing off-screen
        outputs.view = LiveView(outputs.recorder, speed=None, figure=plt.figure()).attach(ep)
    ep.run(seconds, stop_early=False)
    return ep, outputs, load_recording(tmp_path / f"{tag}.npz")


def test_same_seed_same_run_with_and_without_the_live_view(tmp_path):
    _, _, plain = _run(tmp_path, "plain", view=False)
    _, outputs, viewed = _run(tmp_path, "viewed", view=True)
    assert outputs.view is not None and outputs.view.frames_drawn > 0
    assert len(plain) == len(viewed) == 60
    np.testing.assert_array_equal(plain.pose, viewed.pose)
    np.testing.assert_array_equal(plain.proximity, viewed.proximity)
    np.testing.assert_array_equal(plain.layer, viewed.layer)


def test_real_episode_recording_has_every_robot(tmp_path):
    ep, _, rec = _run(tmp_path, "real", view=False, seconds=2.0)
    assert rec.robot_names == tuple(ep.controllers)
    assert rec.meta["scenario"] == "two-robot-pass"
    assert rec.meta["seed"] == 0
    assert rec.meta["backend"] == "embedded"
    assert rec.scene.track is not None
    for name in rec.robot_names:
        s = rec.robot(name)
        assert np.isfinite(s.pose).all() and np.isfinite(s.proximity).all()
        assert s.layers[0] == "FrontObstacleLeftTurn"


def test_attach_writes_gif_and_plots_at_the_end(tmp_path):
    ep = Episode("two-robot-pass", controller="improved", seed=0)
    outputs = attach(ep, record=tmp_path / "run.gif", plots=tmp_path / "plots")
    ep.run(2.0, stop_early=False)
    names = sorted(p.name for p in outputs.written)
    assert names == sorted(
        ["run.gif", "trajectories.png", "arbitration.png", "sensors.png", "wheels.png"]
    )
    with Image.open(tmp_path / "run.gif") as im:
        assert im.n_frames == 6  # 1.95 s of run: one frame per 0.4 s, then the final state


def test_outputs_are_flushed_when_the_run_is_interrupted(tmp_path):
    ep = Episode("two-robot-pass", controller="improved", seed=0)
    attach(ep, record=tmp_path / "run.npz")
    seen = {"n": 0}

    def ctrl_c(_episode):
        seen["n"] += 1
        if seen["n"] == 10:
            raise KeyboardInterrupt

    ep.add_observer(ctrl_c)
    with pytest.raises(KeyboardInterrupt):
        ep.run(5.0)
    assert len(load_recording(tmp_path / "run.npz")) == 10


def test_view_without_a_display_warns_and_runs_on(tmp_path, caplog):
    ep = Episode("two-robot-pass", controller="improved", seed=0)
    outputs = attach(ep, view=True)
    assert outputs.view is None
    assert "--record run.gif" in caplog.text
    ep.run(0.5)


def test_bad_outputs_fail_before_the_run(tmp_path):
    ep = Episode("two-robot-pass", controller="improved", seed=0)
    try:
        with pytest.raises(ValueError, match=r"\.npz"):
            attach(ep, record=tmp_path / "run.avi")
        (tmp_path / "file").write_text("x")
        with pytest.raises(ValueError, match="directory"):
            attach(ep, plots=tmp_path / "file")
    finally:
        ep.connection.close()


def test_live_view_keys_pause_and_step_without_a_window():
    from viz_standin import StandInEpisode

    from puckboard.recording.recorder import Recorder

    ep = StandInEpisode()
    recorder = Recorder.for_episode(ep)
    ep.add_observer(recorder)
    view = LiveView(recorder, speed=None, figure=plt.figure()).attach(ep)

    class Key:
        def __init__(self, key):
            self.key = key

    view._on_key(Key(" "))
    assert view.paused
    view._on_key(Key("n"))
    assert view._steps_allowed == 1
    view._on_key(Key(" "))
    assert not view.paused
    view._on_key(Key("+"))
    assert view.speed == 2.0
    ep.run(1.0)
    assert view.frames_drawn >= 2
    title = view.stage._closeup_titles[0].get_text()
    assert title == "red: FrontObstacleLeftTurn"


def test_replay_plays_a_recording_through_the_live_view():
    from viz_helpers import stand_in_recording

    from puckboard.viz.live import replay

    rec = stand_in_recording(1.0)
    view = replay(rec, speed=None, figure=plt.figure())
    assert view.frames_drawn >= 2
    assert view.stage._clock.get_text() == f"t = {rec.time[-1]:.1f} s"


def test_the_judges_events_are_recorded(tmp_path):
    ep = Episode("two-robot-pass", controller="stock", seed=0)
    attach(ep, record=tmp_path / "run.npz")
    ep.run(8.0)
    rec = load_recording(tmp_path / "run.npz")
    assert rec.meta["events"] == [e.to_dict() for e in ep.judge.events]
    assert rec.meta["events"], "the stock controller's run has events to record"


def test_notebook_inline_view_updates_one_displayed_image(monkeypatch):
    import sys
    import types

    import matplotlib
    from viz_standin import StandInEpisode

    from puckboard.recording.recorder import Recorder

    shown = []

    class Handle:
        def update(self, obj):
            shown.append(obj)

    def display(obj, display_id=False):
        assert display_id is True
        shown.append(obj)
        return Handle()

    fake = types.ModuleType("IPython.display")
    fake.display = display
    monkeypatch.setitem(sys.modules, "IPython", types.ModuleType("IPython"))
    monkeypatch.setitem(sys.modules, "IPython.display", fake)
    monkeypatch.setattr(
        matplotlib, "get_backend", lambda: "module://matplotlib_inline.backend_inline"
    )
    ep = StandInEpisode()
    recorder = Recorder.for_episode(ep)
    ep.add_observer(recorder)
    view = LiveView(recorder, speed=None).attach(ep)
    assert view.notebook and not view.interactive
    ep.run(1.0)
    assert len(shown) == view.frames_drawn >= 2
    assert shown[-1].size == (1024, 576)  # 12.8 x 7.2 in at 80 dpi


def test_the_gif_is_the_same_file_with_or_without_a_view(tmp_path):
    files = []
    for tag, view in (("plain", False), ("viewed", True)):
        ep = Episode("two-robot-pass", controller="improved", seed=0)
        outputs = attach(ep, record=tmp_path / f"{tag}.gif")
        if view:
            outputs.view = LiveView(outputs.recorder, speed=None, figure=plt.figure()).attach(ep)
        ep.run(2.0, stop_early=False)
        files.append((tmp_path / f"{tag}.gif").read_bytes())
    assert files[0] == files[1]


def test_a_window_torn_down_by_ctrl_c_does_not_replace_the_interrupt():
    """Ctrl-C may destroy the Tk window before the view's last redraw (a TclError about
    one time in nine): the user must see the interrupt, not a redraw traceback."""
    from viz_standin import StandInEpisode

    from puckboard.recording.recorder import Recorder

    ep = StandInEpisode()
    recorder = Recorder.for_episode(ep)
    ep.add_observer(recorder)
    view = LiveView(recorder, speed=None, figure=plt.figure()).attach(ep)
    ep.run(0.5)

    class TclError(Exception):
        pass

    def torn_down(_arrays):
        raise TclError('invalid command name ".!canvas"')

    view._draw = torn_down
    try:
        raise KeyboardInterrupt
    except KeyboardInterrupt:
        view.close()  # while the interrupt is being handled: no new exception
    with pytest.raises(TclError):
        view.close()  # outside an interrupt a failing redraw is a real error
