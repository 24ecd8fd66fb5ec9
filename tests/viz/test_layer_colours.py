"""Every layer of one run has a colour of its own, the same in every view: the
arbitration plot, the animation's legend, the replay page and the live view (issue 35,
item 10: LineFollow and LineSearch were both #0072B2)."""

from __future__ import annotations

import matplotlib
import pytest
from matplotlib.colors import to_hex

from puckboard.behaviours import Controller, Cruise, Layer, LineFollow, robust
from puckboard.control.episode import Episode
from puckboard.recording.recorder import Recorder, load_recording
from puckboard.records import WheelCommand
from puckboard.viz.style import layer_colour, layer_colours

matplotlib.use("Agg")


class FindLineOnTheRight(Layer):
    reads = ("ground",)

    def applies(self, frame):
        return frame.ground is not None and min(frame.ground.value.tolist()) > 0.5

    def command(self, frame):
        return WheelCommand(2.0, 1.0)


def tutorial():
    return Controller([LineFollow(), FindLineOnTheRight(), Cruise()], name="tutorial")


@pytest.mark.parametrize("factory", [robust, tutorial])
def test_every_layer_of_a_controller_has_its_own_colour(factory):
    names = [layer.name for layer in factory().every_layer]
    colours = layer_colours(names)
    assert len(set(colours.values())) == len(names), colours
    assert colours["LineFollow"] == layer_colour("LineFollow")  # the first keeps its role's


def test_the_same_layer_of_two_robots_is_one_colour_and_the_specials_keep_theirs():
    colours = layer_colours(["LineFollow", "LineSearch", "LineFollow", "(none)"])
    assert list(colours) == ["LineFollow", "LineSearch", "(none)"]
    assert colours["LineFollow"] != colours["LineSearch"]
    assert colours["(none)"] == layer_colour("(none)")


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    path = tmp_path_factory.mktemp("colours") / "run.npz"
    episode = Episode("two-robot-pass", controller=robust, seed=0)
    Recorder.for_episode(episode, path).attach(episode)
    episode.run(1.0)
    return episode, load_recording(path)


def test_plot_animation_replay_and_live_view_agree(recorded):
    import matplotlib.pyplot as plt

    from puckboard.viz.animation import stage_for_recording
    from puckboard.viz.plots import plot_arbitration
    from puckboard.web.replay import replay_data
    from puckboard.web.state import EpisodeFollower

    episode, rec = recorded
    names = [layer.name for layer in episode.controllers["left"].every_layer]
    expected = layer_colours(names)
    assert "LineSearch" in expected and len(set(expected.values())) == len(names)

    fig = plot_arbitration(rec)
    plotted = {
        h.get_label().split(" (")[0]: to_hex(h.get_facecolor())
        for legend in fig.legends
        for h in legend.legend_handles
    }
    plt.close(fig)
    fig = plt.figure()
    staged = stage_for_recording(fig, rec)._layer_colours
    plt.close(fig)
    replayed = replay_data(rec)["layer_colours"]
    live = EpisodeFollower(episode, lambda kind, data: None).layer_colours
    for name, colour in expected.items():
        assert plotted[name].lower() == colour.lower(), name
        assert staged[name] == replayed[name] == live[name] == colour, name
