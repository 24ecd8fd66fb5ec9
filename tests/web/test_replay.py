"""A recorded run as the player's document: served read-only, exported as one file, and
shown in Jupyter; the live views carry the behaviour tree too."""

from __future__ import annotations

import json
import re
import sys
import time
import types

import numpy as np
import pytest
from recordings import recorded_run
from test_web_stream import get, request

from puckboard.control.episode import Episode
from puckboard.recording.recorder import load_recording
from puckboard.web import watch_episode
from puckboard.web.export import replay_html, write_replay_html
from puckboard.web.replay import replay_data, serve_replay


@pytest.fixture(scope="module")
def recording():
    return load_recording(recorded_run("two-robot-pass"))


def test_the_document_holds_every_tick_of_every_robot(recording):
    data = replay_data(recording)
    t = len(recording)
    assert data["format"] == "puckboard-replay" and data["recording_format"] == 3
    assert len(data["t"]) == t and data["t"][-1] == pytest.approx(recording.time[-1], abs=1e-3)
    assert [r["name"] for r in data["scene"]["robots"]] == ["left", "right"]
    for r, robot in enumerate(data["robots"]):
        np.testing.assert_allclose(
            np.reshape(robot["pose"], (t, 3)), recording.pose[:, r], atol=6e-5
        )
        assert [data["layer_names"][k] for k in robot["layer"][:3]] == [
            recording.robot(r).layer_at(k) for k in range(3)
        ]
        k = len(robot["nodes"])
        assert len(robot["tree"]) == t * k  # one digit per node and tick
        tick = t // 2
        digits = robot["tree"][tick * k : (tick + 1) * k]
        expected = recording.tree_at(r, tick)
        assert {n["name"]: int(c) for n, c in zip(robot["nodes"], digits)} == {
            name: data["tree_status"].index(status) for name, status in expected.items()
        }
        # values identical to the robot's own arrays are sent once
        assert [(x["key"], x["same_as"]) for x in robot["reads"]] == [
            ("ground", "ground"), ("proximity", "proximity"),
        ]  # fmt: skip
    kinds = [e["kind"] for e in data["events"]]
    by_time = sorted(recording.meta["events"], key=lambda e: e["time_s"])
    assert kinds == [e["kind"] for e in by_time] and kinds[-1] == "success"
    json.dumps(data, allow_nan=False)  # strict JSON: NaN became null


def test_a_format_2_recording_gets_a_note_instead_of_a_tree(recording, tmp_path):
    old = recording.save(tmp_path / "r.npz")
    with np.load(old) as d:
        arrays = {k: d[k] for k in ("time", "pose", "wheels", "layer", "proximity", "ground")}
        meta = json.loads(str(d["meta"]))
    meta["version"] = 2
    np.savez(old, meta=np.array(json.dumps(meta)), **arrays)
    data = replay_data(load_recording(old))
    for robot in data["robots"]:
        assert robot["tree"] is None and robot["reads"] == []
        assert "no behaviour-tree data" in robot["tree_note"] and "format 2" in robot["tree_note"]


def test_the_served_replay_is_the_document_and_stays_read_only(recording):
    view = serve_replay(recording, port=0)
    try:
        status, page = get(view.url)
        assert status == 200 and b'id="slider"' in page and b"/replay.js" in page
        assert "<title>puckboard — replay</title>".encode() in page  # not "live view"
        assert get(view.url + "replay.js")[0] == 200
        served = json.loads(get(view.url + "replay.json")[1])
        assert served == json.loads(json.dumps(replay_data(recording)))
        for method in ("POST", "PUT", "DELETE"):
            assert request(view, method, "/replay.json") == 405
        assert request(view, "GET", "/replay.js/../view.js") == 404
    finally:
        view.close()


def test_the_live_view_serves_no_replay(recording):
    episode = Episode("two-robot-pass", seed=0)
    view = watch_episode(episode, port=0, speed=None)
    try:
        episode.run(3.0)
        assert json.loads(get(view.url + "replay.json")[1]) is None
        assert "<title>puckboard — live view</title>".encode() in get(view.url)[1]
    finally:
        view.close()


def test_the_one_file_export_needs_nothing_from_outside(recording, tmp_path):
    path = write_replay_html(recording, tmp_path / "sub" / "pass.html")
    text = path.read_text(encoding="utf-8")
    assert text == replay_html(recording)
    # no file or address to fetch: no src= or href= at all, and a policy refusing requests
    assert not re.search(r"\b(src|href)\s*=", text)
    assert "Content-Security-Policy" in text and "default-src 'none'" in text
    payload = re.search(
        r'<script id="replay-data" type="application/json">(.*?)</script>', text, re.S
    ).group(1)
    assert "</" not in payload
    assert json.loads(payload) == json.loads(json.dumps(replay_data(recording)))
    assert text.count("<script") == 3  # the data, view.js, replay.js
    with pytest.raises(ValueError, match=r"\.html"):
        write_replay_html(recording, tmp_path / "pass.txt")


def test_jupyter_shows_the_player_in_an_iframe(recording, monkeypatch):
    from puckboard.web import show_replay

    display = types.ModuleType("IPython.display")

    class HTML:
        def __init__(self, data):
            self.data = data

    display.HTML = HTML  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "IPython", types.ModuleType("IPython"))
    monkeypatch.setitem(sys.modules, "IPython.display", display)
    shown = show_replay(recording, height=500)
    assert shown.data.startswith("<iframe srcdoc=") and "height: 500px" in shown.data
    assert "&lt;script id=&quot;replay-data&quot;" in shown.data  # the page, escaped
    monkeypatch.setitem(sys.modules, "IPython", None)
    monkeypatch.setitem(sys.modules, "IPython.display", None)
    with pytest.raises(ImportError, match="needs IPython.*puckboard replay RUN.npz --html"):
        show_replay(recording)


def test_the_live_panel_shows_the_tree_with_the_layer_in_control():
    episode = Episode("two-robot-pass", seed=0)
    view = watch_episode(episode, port=0, speed=None)
    try:
        episode.run(10.0)
        details = json.loads(get(view.url + "details.json")[1])
    finally:
        view.close()
    for name in ("left", "right"):
        tree = details[name]["tree"]
        names = [n["name"] for n in tree["nodes"]]
        assert names == [
            "improved",
            "FrontObstacleLeftTurn",
            "LineFollow",
            "SideWallKeep",
            "Cruise",
        ]
        assert tree["active"] == episode.controllers[name].active_layer
        k = names.index(tree["active"])
        assert tree["status"] == [2] + [1] * (k - 1) + [2] + [0] * (len(names) - k - 1)
        assert all(n["colour"].startswith("#") for n in tree["nodes"][1:])


def decoded(signal) -> dict:
    """The tree a puckboard client publishes in its string signal."""
    return json.loads(signal.decode() if isinstance(signal, bytes) else signal)


def status_of(signal) -> list[int] | None:
    """The published tree's node statuses, as the page shows them (None: no tree yet)."""
    return None if signal is None else [int(c) for c in decoded(signal)["status"]]


def test_a_served_world_shows_the_tree_its_puckboard_client_publishes():
    pytest.importorskip("zmq")
    from puckboard.backends.coppeliasim.server.socket_loop import RemoteApiServer
    from puckboard.scenario.scenefile import load_scene
    from puckboard.web import watch_server

    server = RemoteApiServer(load_scene("two-robot-pass"), host="127.0.0.1", port=0).start()
    view = watch_server(server, port=0)
    seen: dict[str, object] = {}

    def look(episode) -> None:
        # the client holds the stepping world here: its page catches up (its observers
        # refresh the details 4x/s, later on a loaded machine), then we compare
        if episode.loop.cycles != 40:
            return
        seen["signal"] = server.api.signals.string.get("ePuck#0.tree")
        seen["layer"] = episode.controllers["left"].active_layer
        deadline = time.monotonic() + 60
        while True:
            seen["details"] = json.loads(get(view.url + "details.json")[1] or b"null")
            tree = (seen["details"] or {}).get("left", {}).get("tree", {})
            if tree.get("status") == status_of(seen["signal"]) or time.monotonic() > deadline:
                break  # the page shows the last step's tree (else the asserts below say so)
            time.sleep(0.05)

    try:
        episode = Episode("two-robot-pass", backend="coppeliasim", port=server.port)
        episode.add_observer(look)
        episode.run(3.0)
    finally:
        view.close()
        server.close()
    published = decoded(seen["signal"])
    tree = seen["details"]["left"]["tree"]
    names = [n["name"] for n in tree["nodes"]]
    assert names == [n["name"] for n in published["nodes"]]
    assert names == ["improved", "FrontObstacleLeftTurn", "LineFollow", "SideWallKeep", "Cruise"]
    assert tree["status"] == [int(c) for c in published["status"]]
    assert tree["active"] == seen["layer"] and tree["status"][names.index(seen["layer"])] == 2
