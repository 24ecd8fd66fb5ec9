"""The replay in a real headless browser: the slider, the arrow keys and the events move
the robots to their recorded poses, the tree shows the recorded statuses, and the one-file
export plays from disk with the network off. Skipped where no Chromium is found."""

from __future__ import annotations

import time

import pytest
from browser import Browser, chromium
from recordings import recorded_run

from puckboard.recording.recorder import load_recording
from puckboard.web.export import write_replay_html
from puckboard.web.replay import serve_replay

BINARY = chromium()
pytestmark = pytest.mark.skipif(
    BINARY is None,
    reason="no Chromium found (chromium, chromium-browser, google-chrome); install Debian's "
    "'chromium' package, as .ci/run does, to run the browser tests",
)

READY = "window.state && state.player && state.readyAt"


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    folder = tmp_path_factory.mktemp("replay-browser")
    rec = load_recording(recorded_run("two-robot-pass"))
    return rec, write_replay_html(rec, folder / "pass.html")


@pytest.fixture
def served(recorded):
    view = serve_replay(recorded[0], port=0)
    yield recorded[0], view
    view.close()


def move_slider(browser: Browser, tick: int) -> None:
    browser.evaluate(
        f"(() => {{ const s = document.getElementById('slider'); s.value = {tick}; "
        "s.dispatchEvent(new Event('input', { bubbles: true })); })()"
    )


def drawn_colours(browser: Browser) -> list[list[str]]:
    """Per robot: the canvas colour beside its heading line, and the robot's colour."""
    return browser.evaluate("""(() => {
        const c = document.getElementById('arena'), g = c.getContext('2d');
        return state.frame.robots.map((r, i) => {
          const side = 0.6 * state.scene.robots[i].radius, th = r.pose[2] + Math.PI / 2;
          const [u, w] = px(r.pose[0] + side * Math.cos(th), r.pose[1] + side * Math.sin(th));
          const d = g.getImageData(Math.round(u), Math.round(w), 1, 1).data;
          const hex = '#' + [d[0], d[1], d[2]].map(v => v.toString(16).padStart(2, '0')).join('');
          return [hex, state.scene.robots[i].colour.toLowerCase()];
        });
    })()""")


def close(got: str, want: str) -> bool:
    return all(abs(int(got[k : k + 2], 16) - int(want[k : k + 2], 16)) <= 8 for k in (1, 3, 5))


def test_moving_the_slider_puts_the_robots_where_the_recording_has_them(served):
    rec, view = served
    with Browser(BINARY) as browser:
        browser.open(view.url)
        browser.wait_for(READY)
        assert browser.evaluate("+document.getElementById('slider').max") == len(rec) - 1
        for tick in (0, 166, len(rec) // 2, len(rec) - 1):
            move_slider(browser, tick)
            assert browser.evaluate("state.player.index") == tick
            assert browser.evaluate("state.frame.t") == pytest.approx(rec.time[tick], abs=1e-3)
            poses = browser.evaluate("state.frame.robots.map(r => r.pose)")
            for r, pose in enumerate(poses):
                assert pose == pytest.approx(list(rec.pose[tick, r]), abs=1e-4)
            for got, want in drawn_colours(browser):  # and they are drawn there
                assert close(got, want), (tick, got, want)
        shown = browser.evaluate("document.getElementById('time').textContent")
        assert shown == f"t = {rec.time[-1]:.1f} s"


def test_the_arrow_keys_step_one_control_tick(served):
    rec, view = served
    with Browser(BINARY) as browser:
        browser.open(view.url)
        browser.wait_for(READY)
        move_slider(browser, 100)
        browser.evaluate("document.activeElement.blur()")
        for key, code, expected in (("ArrowRight", 39, 101), ("ArrowRight", 39, 102),
                                    ("ArrowLeft", 37, 101)):  # fmt: skip
            for kind in ("keyDown", "keyUp"):
                browser.call("Input.dispatchKeyEvent", type=kind, key=key, code=key,
                             windowsVirtualKeyCode=code)  # fmt: skip
            assert browser.evaluate("state.player.index") == expected
        poses = browser.evaluate("state.frame.robots.map(r => r.pose)")
        assert poses[0] == pytest.approx(list(rec.pose[101, 0]), abs=1e-4)


def test_clicking_an_event_jumps_to_its_time(served):
    rec, view = served
    events = sorted(rec.meta["events"], key=lambda e: e["time_s"])
    with Browser(BINARY) as browser:
        browser.open(view.url)
        browser.wait_for(READY)
        assert browser.evaluate("document.querySelectorAll('#events li').length") == len(events)
        for k in (2, len(events) // 2):
            browser.evaluate(f"document.querySelectorAll('#events li')[{k}].click()")
            t = browser.evaluate("state.frame.t")
            tick = int(abs(rec.time - events[k]["time_s"]).argmin())
            assert browser.evaluate("state.player.index") == tick
            assert t == pytest.approx(events[k]["time_s"], abs=1e-6)  # a tick at that very time
            current = browser.evaluate("document.querySelector('#events li.current').textContent")
            assert current.startswith(f"{events[k]['time_s']:.1f} s")


def test_the_tree_at_a_tick_shows_the_recorded_statuses_and_who_drove(served):
    rec, view = served
    codes = rec.meta.get("tree_status") or [
        "not ticked",
        "FAILURE",
        "RUNNING",
        "SUCCESS",
        "INVALID",
    ]
    with Browser(BINARY) as browser:
        browser.open(view.url)
        browser.wait_for(READY)
        browser.evaluate("document.querySelector('#robots tbody tr[data-robot=\"right\"]').click()")
        series = rec.robot("right")
        ticks = {}
        for i in range(len(rec)):  # the first tick each layer drove
            ticks.setdefault(series.layer_at(i), i)
        assert len(ticks) >= 3
        for layer, tick in ticks.items():
            move_slider(browser, tick)
            shown = browser.evaluate(
                "Array.from(document.querySelectorAll('#tree li')).map(e => "
                "[e.dataset.node, +e.dataset.status, e.classList.contains('in-control')])"
            )
            assert {name: codes[code] for name, code, _ in shown} == rec.tree_at("right", tick)
            assert [name for name, _, marked in shown if marked] == [layer]
            assert browser.evaluate("document.getElementById('panel-title').textContent") == "right"


def test_the_offline_file_plays_from_disk_with_the_network_off(recorded):
    rec, path = recorded
    with Browser(BINARY) as browser:
        browser.call("Network.enable")
        browser.call("Network.emulateNetworkConditions", offline=True, latency=0,
                     downloadThroughput=-1, uploadThroughput=-1)  # fmt: skip
        browser.open(path.as_uri())
        browser.wait_for(READY)
        assert browser.evaluate("state.scene.robots.map(r => r.name)") == ["left", "right"]
        assert browser.evaluate("document.getElementById('player').hidden") is False
        browser.evaluate(
            "document.getElementById('speed').value = '8'; "
            "document.getElementById('speed').dispatchEvent(new Event('change'))"
        )
        browser.evaluate("document.getElementById('play').click()")
        time.sleep(1.0)
        first = browser.evaluate("state.player.index")
        time.sleep(0.5)
        later = browser.evaluate("state.player.index")
        assert 0 < first < later  # it plays: 8x real time is 160 ticks a second
        assert browser.evaluate("state.player.playing") is True
        browser.evaluate("document.getElementById('play').click()")
        tick = browser.evaluate("state.player.index")
        poses = browser.evaluate("state.frame.robots.map(r => r.pose)")
        assert poses[1] == pytest.approx(list(rec.pose[tick, 1]), abs=1e-4)
        # a clicked robot: its tree, with the layer in control marked
        browser.evaluate("document.querySelector('#robots tbody tr[data-robot=\"left\"]').click()")
        marked = browser.evaluate("document.querySelector('#tree li.in-control').dataset.node")
        assert marked == rec.robot("left").layer_at(tick)


def test_an_older_recording_replays_and_its_panel_says_the_tree_is_missing(recorded, tmp_path):
    import json

    import numpy as np

    rec, _ = recorded
    old = rec.save(tmp_path / "old.npz")
    with np.load(old) as d:
        arrays = {k: d[k] for k in ("time", "pose", "wheels", "layer", "proximity", "ground")}
        meta = json.loads(str(d["meta"]))
    meta["version"] = 2
    np.savez(old, meta=np.array(json.dumps(meta)), **arrays)
    page = write_replay_html(load_recording(old), tmp_path / "old.html")
    with Browser(BINARY) as browser:
        browser.open(page.as_uri())
        browser.wait_for(READY)
        move_slider(browser, 300)
        browser.evaluate("document.querySelector('#robots tbody tr[data-robot=\"left\"]').click()")
        note = browser.evaluate("document.getElementById('tree-note').textContent")
        assert "no behaviour-tree data" in note and "format 2" in note
        assert browser.evaluate("document.getElementById('tree-note').hidden") is False
        assert browser.evaluate("document.querySelectorAll('#tree li').length") == 0
        keys = browser.evaluate(
            "Array.from(document.querySelectorAll('#keys tbody td:first-child'))"
            ".map(e => e.textContent)"
        )
        assert keys == ["proximity", "ground", "command/layer", "command/wheels"]
        assert browser.evaluate("state.frame.robots[0].pose") == pytest.approx(
            list(rec.pose[300, 0]), abs=1e-4
        )
