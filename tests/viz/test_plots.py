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
