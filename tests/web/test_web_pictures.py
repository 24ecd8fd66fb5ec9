"""Pictures legible on a projector and in a class: dark text on light layer colours
(web chips and the tree's PNG alike), a camera that is off shown as off, not as a
fault, and an offline replay that opens with a robot's tree shown (issue 30, round 4,
item 17). The browser tests are skipped where no Chromium is found."""

from __future__ import annotations

import pytest
from browser import Browser, chromium

from puckboard.behaviours.presets import load_controller
from puckboard.control.episode import Episode
from puckboard.recording import Recorder, load_recording
from puckboard.viz.style import layer_colour, text_colour
from puckboard.viz.tree import tree_dot
from puckboard.web.export import write_replay_html
from puckboard.web.state import EpisodeFollower

BINARY = chromium()
needs_chromium = pytest.mark.skipif(BINARY is None, reason="no Chromium found")


@pytest.mark.parametrize(
    ("background", "text"),
    [
        ("#E69F00", "#000000"),
        ("#F0E442", "#000000"),
        ("#0072B2", "#ffffff"),
        ("#8C564B", "#ffffff"),
    ],
)
def test_text_on_a_colour_is_the_one_that_contrasts_more(background, text):
    assert text_colour(background) == text


def test_the_tree_picture_writes_dark_text_on_the_orange_layer():
    dot = tree_dot(load_controller("improved"))
    line = next(x for x in dot.splitlines() if "SideWallKeep" in x and "fillcolor" in x)
    assert layer_colour("SideWallKeep").lower() == "#e69f00"
    assert 'fontcolor="#000000"' in line, line


def test_a_sensor_that_is_off_is_shown_as_off_not_missing():
    episode = Episode("two-robot-pass", seed=0)
    sent: list[tuple[str, object]] = []
    follower = EpisodeFollower(episode, lambda kind, data: sent.append((kind, data)))
    episode.add_observer(lambda _ep: follower.update(force=True))
    episode.run(0.2)
    details = [data for kind, data in sent if kind == "details"][-1]
    keys = {k["key"]: k for k in details["left"]["keys"]}  # type: ignore[index]
    assert keys["camera"]["status"] == "off" and keys["camera"]["value"] == "off"
    assert keys["proximity"]["status"] == "fresh"


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    folder = tmp_path_factory.mktemp("pictures")
    episode = Episode("two-robot-pass", seed=0)
    Recorder.for_episode(episode, folder / "pass.npz").attach(episode)
    episode.run(3.0)
    return write_replay_html(load_recording(folder / "pass.npz"), folder / "pass.html")


@needs_chromium
def test_the_offline_replay_opens_with_a_robot_and_its_tree_shown(page):
    with Browser(BINARY) as browser:
        browser.open(page.as_uri())
        browser.wait_for("window.state && state.player && state.readyAt")
        assert browser.evaluate("state.selected") == "left"
        assert browser.evaluate("document.getElementById('panel').hidden") is False
        assert browser.evaluate("document.querySelectorAll('#tree li').length") > 0


@needs_chromium
def test_the_page_picks_the_text_colour_as_the_tree_picture_does(page):
    colours = ["#E69F00", "#0072B2", "#D55E00", "#8C564B", "#F0E442", "#4DAF4A", "#56B4E9"]
    with Browser(BINARY) as browser:
        browser.open(page.as_uri())
        browser.wait_for("window.state && state.player && state.readyAt")
        shown = browser.evaluate(f"{colours}.map(textOn)")
    assert shown == [text_colour(c) for c in colours]
