import xml.etree.ElementTree as ET

import pytest
from PIL import Image
from viz_helpers import stand_in_recording

from puckboard.viz.plots import layer_spans, save_plots


@pytest.fixture(scope="module")
def rec():
    return stand_in_recording(2.0)


def test_png_plots_exist_open_and_have_their_size(rec, tmp_path):
    paths = save_plots(rec, tmp_path, "png")
    assert [p.name for p in paths] == [
        "trajectories.png",
        "arbitration.png",
        "sensors.png",
        "wheels.png",
    ]
    sizes = {}
    for p in paths:
        with Image.open(p) as im:
            assert im.format == "PNG"
            sizes[p.stem] = im.size
    assert sizes["trajectories"] == (1000, 650)
    assert sizes["arbitration"] == (1200, round(100 * (2.4 + 0.85 * 2)))
    assert sizes["sensors"][1] == round(100 * (1.0 + 3.6 * 2))


def test_svg_plots_parse_and_name_the_robots_and_layers(rec, tmp_path):
    paths = save_plots(rec, tmp_path, "svg")
    for p in paths:
        root = ET.parse(p).getroot()
        assert root.tag.endswith("svg")
    text = (tmp_path / "arbitration.svg").read_text()
    for word in ("red", "blue", "FrontObstacleLeftTurn", "LineFollow", "stand-in"):
        assert word in text


def test_arbitration_spans_follow_the_recorded_layers(rec):
    red = layer_spans(rec, "red")
    blue = layer_spans(rec, "blue")
    assert [s[0] for s in red] == ["FrontObstacleLeftTurn"]
    assert [s[0] for s in blue] == ["LineFollow"]
    assert red[0][1] == 0.0
    assert red[0][2] == pytest.approx(2.0)


def test_bad_format_and_empty_recordings_are_refused(rec, tmp_path):
    with pytest.raises(ValueError, match="png, svg"):
        save_plots(rec, tmp_path, "jpg")


def test_layer_colours_stay_apart_from_every_shipped_robot_colour():
    """A timeline shows robots and layers side by side: the default layer (Cruise) must
    not look like a robot (it was a light green next to the green robot 'left')."""
    from puckboard.scenario import load_scene, scene_names
    from puckboard.viz.style import layer_colour

    def rgb(hex_colour):
        return tuple(int(hex_colour[k : k + 2], 16) for k in (1, 3, 5))

    mine = rgb(layer_colour("Cruise"))
    for name in scene_names():
        for robot in load_scene(name).robots:
            gap = sum((a - b) ** 2 for a, b in zip(mine, robot.colour)) ** 0.5
            assert gap > 90, (name, robot.name, gap)


def test_wheel_plot_says_wheel_for_the_lines_and_robot_for_the_panels(rec):
    """'left'/'right' name both a robot and a wheel in the two-robot pass: say which."""
    from puckboard.viz.plots import plot_wheels

    fig = plot_wheels(rec)
    for ax in fig.axes:
        labels = [t.get_text() for t in ax.get_legend().get_texts()]
        assert labels == ["left wheel", "right wheel"]
        assert ax.get_title(loc="left").startswith("robot ")


@pytest.fixture(scope="module")
def two_robot_pass():
    from recordings import recorded_run

    from puckboard.recording.recorder import load_recording

    return load_recording(recorded_run("two-robot-pass"))


def test_obstacle_names_on_the_trajectories_are_covered_by_nothing(two_robot_pass):
    """Each obstacle's name beside it, clear of every start and end marker (the left
    robot of seed 0 ends right under the west cylinder, where its name was), of the
    obstacles, the legend, the other names and the track; measured as drawn."""
    from matplotlib.lines import Line2D

    from puckboard.viz.plots import plot_trajectories

    rec = two_robot_pass
    fig = plot_trajectories(rec)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    names = [ob.name for ob in rec.scene.obstacles]
    labels = [t for t in ax.texts if t.get_text() in names]
    assert sorted(t.get_text() for t in labels) == sorted(names)
    markers = [
        line for line in ax.lines
        if isinstance(line, Line2D) and line.get_marker() not in (None, "", "None")
    ]  # fmt: skip
    assert len(markers) == 2 * len(rec.robot_names)  # a start and an end each
    others = [m.get_window_extent(renderer) for m in markers]
    others += [
        p.get_window_extent(renderer) for p in ax.patches if p.get_zorder() == 3
    ]  # obstacles
    others.append(ax.get_legend().get_window_extent(renderer))
    inside = ax.get_window_extent(renderer)
    track = ax.patches[0]
    assert track.get_zorder() == 1  # the track's ink, drawn first
    ink = track.get_transform().transform_path(track.get_path())
    for label in labels:
        box = label.get_window_extent(renderer)
        for other in [*others, *(t.get_window_extent(renderer) for t in labels if t is not label)]:
            assert not box.overlaps(other), (label.get_text(), box, other)
        assert inside.x0 <= box.x0 and box.x1 <= inside.x1  # within the axes
        assert inside.y0 <= box.y0 and box.y1 <= inside.y1
        assert not ink.intersects_bbox(box, filled=True), label.get_text()  # not on the track
        ob = next(o for o in rec.scene.obstacles if o.name == label.get_text())
        centre = ax.transData.transform((ob.x, ob.y))
        reach = ax.transData.transform((ob.x + ob.radius, ob.y))[0] - centre[0]
        gap = max(box.x0 - centre[0], centre[0] - box.x1, box.y0 - centre[1], centre[1] - box.y1)
        assert gap < reach + 10, label.get_text()  # beside its obstacle, not anywhere
