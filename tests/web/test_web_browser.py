"""The page in a real headless browser: every robot is drawn and named, time advances,
clicking a robot opens its panel. Skipped (with the reason) where no Chromium is found;
``.ci/run`` installs Debian's ``chromium``."""

from __future__ import annotations

import contextlib
import threading
import time

import pytest
from browser import Browser, chromium

from puckboard.control.episode import Episode
from puckboard.web import watch_episode

BINARY = chromium()
pytestmark = pytest.mark.skipif(
    BINARY is None,
    reason="no Chromium found (chromium, chromium-browser, google-chrome); install Debian's "
    "'chromium' package, as .ci/run does, to run the browser tests",
)


@pytest.fixture
def live_run():
    episode = Episode("two-robot-pass", seed=0)
    view = watch_episode(episode, port=0, speed=1.0)  # real time: a page has time to watch
    stop = threading.Event()

    def stop_when_told(_episode) -> None:
        if stop.is_set():
            raise KeyboardInterrupt  # ends the run as Ctrl-C does: wheels zeroed, closed

    episode.add_observer(stop_when_told)
    runner = threading.Thread(target=lambda: _run(episode), daemon=True)
    runner.start()
    yield view
    stop.set()
    runner.join(10)
    view.close()


def _run(episode):
    with contextlib.suppress(KeyboardInterrupt):
        episode.run(120.0)


def test_the_page_draws_every_robot_and_time_advances(live_run):
    assert BINARY is not None
    with Browser(BINARY) as browser:
        browser.open(live_run.url)
        names = browser.wait_for(
            "Array.from(document.querySelectorAll('#robots tbody tr')).map(r => r.dataset.robot)"
        )
        assert names == ["left", "right"]
        first = browser.wait_for("window.state && state.frame && state.frame.t")
        time.sleep(1.5)
        later = browser.evaluate("state.frame.t")
        assert later > first + 0.5  # it streams: real time, so about 1.5 s later
        shown = browser.evaluate("document.getElementById('time').textContent")
        assert shown.startswith("t = ")
        # the trails go back to the start, though the page was opened after it
        starts = browser.evaluate("state.scene.robots.map(r => state.trails[r.name][0])")
        assert starts == [pytest.approx(list(t[0])) for t in live_run.follower.trails]
        layers = browser.evaluate(
            "Array.from(document.querySelectorAll('#robots .layer')).map(e => e.textContent)"
        )
        assert len(layers) == 2 and all(layers)
        # the canvas shows the robots: their colours are on it where the frame puts them
        drawn = browser.evaluate("""(() => {
            const c = document.getElementById('arena'), g = c.getContext('2d');
            return state.frame.robots.map((r, i) => {
              const side = 0.6 * state.scene.robots[i].radius, th = r.pose[2] + Math.PI / 2;
              const [u, w] = px(r.pose[0] + side * Math.cos(th), r.pose[1] + side * Math.sin(th));
              const d = g.getImageData(Math.round(u), Math.round(w), 1, 1).data;
              const hex = '#' + [d[0], d[1], d[2]]
                .map(v => v.toString(16).padStart(2, '0')).join('');
              return [hex, state.scene.robots[i].colour.toLowerCase()];
            });
        })()""")
        for got, want in drawn:  # each body, beside its heading line, in the robot's colour
            assert all(
                abs(int(got[k : k + 2], 16) - int(want[k : k + 2], 16)) <= 8 for k in (1, 3, 5)
            ), drawn


def test_clicking_a_robot_opens_its_panel(live_run):
    assert BINARY is not None
    with Browser(BINARY) as browser:
        browser.open(live_run.url)
        browser.wait_for("window.state && state.frame && state.frame.robots.length == 2")
        browser.evaluate("document.querySelector('#robots tbody tr[data-robot=\"right\"]').click()")
        keys = browser.wait_for(
            "document.getElementById('panel').hidden == false && "
            "Array.from(document.querySelectorAll('#keys tbody td:first-child'))"
            ".map(e => e.textContent)"
        )
        assert {"proximity", "ground", "command/layer"} <= set(keys)
        assert browser.evaluate("document.getElementById('panel-title').textContent") == "right"
        # the behaviour tree, live: every layer with its status, the one in control marked
        nodes = browser.wait_for(
            "Array.from(document.querySelectorAll('#tree li')).map(e => e.dataset.node)"
        )
        assert nodes == [
            "improved",
            "FrontObstacleLeftTurn",
            "LineFollow",
            "SideWallKeep",
            "Cruise",
        ]
        marked = browser.wait_for(
            "document.querySelector('#tree li.in-control') && "
            "[document.querySelector('#tree li.in-control').dataset.node, "
            "document.querySelector('#robots tr[data-robot=\"right\"] .layer').textContent]"
        )
        assert marked[0] in nodes[1:] and marked[1] in nodes[1:]


RESTORED_PAGE = """(() => ({
  banner: document.getElementById('verdict').hidden
    ? null : document.getElementById('verdict').textContent,
  status: document.getElementById('status').textContent,
  title: document.getElementById('events').previousElementSibling.textContent,
  events: document.querySelectorAll('#events li').length,
  // how far each robot's trail strays from where the robot now is
  strays: state.frame.robots.map(r => Math.max(0, ...(state.trails[r.name] || []).map(
    ([x, y]) => Math.hypot(x - r.pose[0], y - r.pose[1])))),
  previous: state.frame.robots.map(
    r => ((state.previous || { trails: {} }).trails[r.name] || []).length),
}))()"""


def restored(browser: Browser) -> dict:
    """The page once it shows the restored scene (time 0, stopped) and has had a moment
    to fetch what it needs."""
    browser.wait_for(
        "window.state && state.frame && state.frame.t === 0 && state.frame.status == 'stopped'"
    )
    time.sleep(1.0)
    return browser.evaluate(RESTORED_PAGE)


def test_a_restored_served_world_shows_the_run_that_ended_as_the_previous_run():
    """A client's run ends with sim.stopSimulation: the robots are back at their start.
    A page watching then, and one opened after, draw no trail from where the robots ended
    back to the start, and say that the verdict and events are the previous run's."""
    pytest.importorskip("zmq")
    from puckboard.backends.coppeliasim.server.socket_loop import RemoteApiServer
    from puckboard.control.episode import run_episode
    from puckboard.scenario.scenefile import load_scene
    from puckboard.web import watch_server

    assert BINARY is not None
    server = RemoteApiServer(load_scene("two-robot-pass"), host="127.0.0.1", port=0).start()
    view = watch_server(server, port=0)
    try:
        with Browser(BINARY) as watching:
            watching.open(view.url)
            watching.wait_for("window.state && state.frame && state.frame.status == 'stopped'")
            result = run_episode(
                "two-robot-pass", duration=8.0, backend="coppeliasim", port=server.port
            )
            seen = [restored(watching)]
        with Browser(BINARY) as opened_after:
            opened_after.open(view.url)
            seen.append(restored(opened_after))
    finally:
        view.close()
        server.close()
    assert result.failure == "not_passed"  # 8 s: time ran out before the robots met
    for page in seen:
        assert page["banner"] == "previous run: FAILED: not passed"
        assert page["status"] == "stopped · scene restored"
        assert page["title"] == f"Events of the previous run (ended at {result.sim_time_s:.1f} s)"
        assert page["events"] == len(result.events)
        assert max(page["strays"]) < 1e-3  # a new trail, from the start
        assert min(page["previous"]) > 20  # the run that ended, drawn as such
