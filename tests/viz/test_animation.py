import sys

import numpy as np
import pytest
from PIL import Image
from viz_helpers import stand_in_recording

from puckboard.viz.animation import (
    VideoSupportError,
    check_animation_path,
    frame_indices,
    render_animation,
)


@pytest.fixture(scope="module")
def rec():
    return stand_in_recording(4.0)


def test_frame_indices_sample_run_time_at_speed_over_fps(rec):
    idx = frame_indices(rec, fps=10, speed=4)
    # 3.95 s of run at 0.4 s of run per frame -> frames at 0, 0.4, ..., 3.6, then the
    # final state at 3.95 s
    assert len(idx) == 11
    np.testing.assert_allclose(rec.time[idx[:-1]], np.arange(10) * 0.4, atol=1e-9)
    assert idx[-1] == len(rec) - 1


def test_gif_has_the_expected_frames_and_size(rec, tmp_path):
    out = tmp_path / "run.gif"
    info = render_animation(rec, out, fps=10, speed=4, size=(320, 180))
    assert out.is_file() and info["bytes"] == out.stat().st_size
    with Image.open(out) as im:
        assert im.format == "GIF"
        assert im.size == (320, 180)
        assert im.n_frames == info["frames"] == len(frame_indices(rec, 10, 4))
        assert im.info["duration"] == 100
        im.seek(im.n_frames - 1)
        last = np.asarray(im.convert("RGB"))
    # the robots are drawn in their scene colours (red robot: 200, 40, 40)
    reds = (abs(last[..., 0].astype(int) - 200) < 12) & (last[..., 1] < 60) & (last[..., 2] < 60)
    assert reds.sum() > 20


def test_gif_is_identical_when_rendered_twice(rec, tmp_path):
    a = render_animation(rec, tmp_path / "a.gif", speed=16, size=(320, 180))["path"].read_bytes()
    b = render_animation(rec, tmp_path / "b.gif", speed=16, size=(320, 180))["path"].read_bytes()
    assert a == b


def test_mp4_frame_count(rec, tmp_path):
    pytest.importorskip("imageio_ffmpeg")
    import imageio.v2 as imageio

    out = tmp_path / "run.mp4"
    info = render_animation(rec, out, fps=10, speed=8, size=(320, 176))
    reader = imageio.get_reader(out)
    try:
        assert reader.count_frames() == info["frames"]
        assert reader.get_data(0).shape == (176, 320, 3)
    finally:
        reader.close()


def test_missing_mp4_support_says_how_to_install(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", None)
    with pytest.raises(VideoSupportError, match=r"pip install 'puckboard\[video\]'"):
        check_animation_path(tmp_path / "x.mp4")
    check_animation_path(tmp_path / "x.gif")  # GIFs need no ffmpeg


def test_bad_suffix_is_refused(tmp_path):
    with pytest.raises(ValueError, match=r"\.gif or \.mp4"):
        check_animation_path(tmp_path / "x.avi")


def test_part_of_a_run_and_bad_windows(rec):
    idx = frame_indices(rec, fps=10, speed=2, start=1.0, end=2.0)
    np.testing.assert_allclose(rec.time[idx], 1.0 + np.arange(6) * 0.2, atol=1e-9)
    idx = frame_indices(rec, fps=10, speed=2, start=1.0, end=2.1)
    np.testing.assert_allclose(rec.time[idx[-2:]], [2.0, 2.1], atol=1e-9)
    with pytest.raises(ValueError, match="nothing to animate"):
        frame_indices(rec, fps=10, speed=2, start=10.0)


def test_plot_cli_writes_plots_and_a_sized_animation(rec, tmp_path, capsys):
    from puckboard.cli import main

    rec.save(tmp_path / "run.npz")
    gif = tmp_path / "clip.gif"
    argv = ["plot", str(tmp_path / "run.npz"), "--out", str(tmp_path / "plots")]
    assert main([*argv, "--animate", str(gif), "--size", "320x180", "--to", "1"]) == 0
    assert sorted(p.name for p in (tmp_path / "plots").iterdir()) == [
        "arbitration.png",
        "sensors.png",
        "trajectories.png",
        "wheels.png",
    ]
    with Image.open(gif) as im:
        assert im.size == (320, 180)
        assert im.n_frames == 4  # 0, 0.4, 0.8 s and the last state shown, 1.0 s
    assert "4 frames" in capsys.readouterr().out
    assert main([*argv, "--animate", str(tmp_path / "x.avi")]) == 2
    assert main(["plot", str(tmp_path / "missing.npz")]) == 2


def test_judge_events_are_shown_for_a_few_seconds(rec):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from puckboard.viz.animation import draw_row, stage_for_recording

    rec.meta["events"] = [{"time_s": 0.55, "robot": "red", "kind": "passed_other"}]
    try:
        fig = Figure(figsize=(6.4, 3.6))
        FigureCanvasAgg(fig)
        stage = stage_for_recording(fig, rec)
        shown = {}
        for t in (0.45, 0.5, 3.5, 3.6):
            draw_row(stage, rec, int(np.searchsorted(rec.time, t - 1e-9)))
            shown[t] = stage._news.get_text()
        # stamped at the end of the cycle that sensed at 0.5 s; gone 3 s later
        news = "red: passed the other robot"
        assert shown == {0.45: "", 0.5: news, 3.5: news, 3.6: ""}
    finally:
        del rec.meta["events"]


def test_a_robot_without_a_pose_is_still_shown_robot_centred(rec):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from puckboard.viz.animation import stage_for_recording

    fig = Figure(figsize=(6.4, 3.6))
    FigureCanvasAgg(fig)
    stage = stage_for_recording(fig, rec)
    pose = rec.pose[5].copy()
    pose[0] = np.nan  # the first robot has no pose (a real robot)
    stage.update(1.0, pose, rec.proximity[5], rec.ground[5], ["Cruise", "LineFollow"])
    stage.frame_rgb()
    red_closeup = stage._artists[1]["robots"][0]
    assert red_closeup["body"].get_visible()
    x, y = red_closeup["body"].center
    xmin, xmax = stage.closeups[0].get_xlim()
    assert xmin < x < xmax and x > 1000  # far from the scene, centred in its close-up
    assert "robot-centred" in stage.closeups[0].xaxis.label.get_text()
    assert "cm wide" in stage.closeups[1].xaxis.label.get_text()
    ox0, ox1 = stage.overview.get_xlim()
    assert ox1 < 100  # the overview still shows the scene, not the stand-in spot


@pytest.mark.parametrize(
    ("size", "says"),
    [
        ("100000x100000", "--size must be at most 3840x2160 pixels (4K; each frame is held in "
                          "memory), got 100000x100000"),
        ("100x50", "--size must be at least 160x90 pixels, got 100x50"),
    ],
)  # fmt: skip
def test_an_animation_size_that_cannot_fit_is_refused_before_anything_is_drawn(
    rec, tmp_path, capsys, size, says
):
    from puckboard.cli import main

    rec.save(tmp_path / "run.npz")
    gif = tmp_path / "clip.gif"
    argv = ["plot", str(tmp_path / "run.npz"), "--animate", str(gif), "--size", size]
    assert main([*argv, "--to", "1"]) == 2
    assert capsys.readouterr().err.strip() == f"puckboard plot: error: {says}"
    assert not gif.exists()
    with pytest.raises(ValueError, match="at most 3840x2160"):
        render_animation(rec, gif, size=(4000, 100))
