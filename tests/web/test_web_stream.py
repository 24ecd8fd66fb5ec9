"""The web view over plain HTTP: what it serves, that it is read-only, that it streams."""

from __future__ import annotations

import http.client
import itertools
import json
import math
import time
import urllib.error
import urllib.request

import pytest

from puckboard.control.episode import Episode, run_episode
from puckboard.web import watch_episode, watch_server


def get(url: str) -> tuple[int, bytes]:
    try:
        with urllib.request.urlopen(url, timeout=10) as r:
            return r.status, r.read()
    except urllib.error.HTTPError as exc:
        return exc.code, b""


def request(view, method: str, path: str) -> int:
    conn = http.client.HTTPConnection("127.0.0.1", view.port, timeout=10)
    try:
        conn.request(method, path)
        return conn.getresponse().status
    finally:
        conn.close()


def stream_frames(view, count: int, timeout: float = 10.0) -> list[dict]:
    """The first ``count`` frames of /stream, as a browser's EventSource sees them."""
    frames = []
    conn = http.client.HTTPConnection("127.0.0.1", view.port, timeout=timeout)
    try:
        conn.request("GET", "/stream")
        response = conn.getresponse()
        assert response.getheader("Content-Type").startswith("text/event-stream")
        kind = None
        deadline = time.monotonic() + timeout
        while len(frames) < count and time.monotonic() < deadline:
            line = response.fp.readline().decode().rstrip("\n")
            if line.startswith("event: "):
                kind = line[7:]
            elif line.startswith("data: ") and kind == "frame":
                frames.append(json.loads(line[6:]))
    finally:
        conn.close()
    return frames


@pytest.fixture
def finished_run():
    episode = Episode("two-robot-pass", seed=0)
    view = watch_episode(episode, port=0, speed=None)
    result = episode.run(30.0)
    yield view, result
    view.close()


def test_page_scene_and_final_frame(finished_run):
    view, result = finished_run
    status, page = get(view.url)
    assert status == 200 and b'<canvas id="arena"' in page and b"/view.js" in page
    assert get(view.url + "view.js")[0] == 200 and get(view.url + "view.css")[0] == 200
    scene = json.loads(get(view.url + "scene.json")[1])
    assert [r["name"] for r in scene["robots"]] == ["left", "right"]
    assert len(scene["obstacles"]) == 2 and scene["track"]["closed"]
    frame = json.loads(get(view.url + "frame.json")[1])
    assert frame["status"] == "finished" and frame["t"] == pytest.approx(result.sim_time_s)
    assert [e["kind"] for e in frame["events"]] == [
        e.kind for e in sorted(result.events, key=lambda e: e.time_s)
    ]
    assert frame["verdict"]["success"] == result.success
    for r in frame["robots"]:
        assert r["layer"] in {"FrontObstacleLeftTurn", "LineFollow", "SideWallKeep", "Cruise"}
        assert r["layer_colour"].startswith("#") and len(r["prox"]) == 8
    details = json.loads(get(view.url + "details.json")[1])
    keys = {k["key"] for k in details["left"]["keys"]}
    assert {"proximity", "ground", "command/layer", "command/wheels"} <= keys
    timeline = details["left"]["timeline"]
    assert timeline[0]["t"] <= 0.1 and [c["t"] for c in timeline] == sorted(
        c["t"] for c in timeline
    )
    trails = json.loads(get(view.url + "trails.json")[1])
    assert len(trails["trails"]["left"]) > 50 and trails["previous"] is None
    assert trails["run"] == frame["run"] == 0


def test_the_view_is_read_only_and_serves_nothing_else(finished_run):
    view, _ = finished_run
    for method in ("POST", "PUT", "DELETE"):
        assert request(view, method, "/") == 405
        assert request(view, method, "/stream") == 405
    for path in ("/static/view.js", "/../pyproject.toml", "/view.js/../../setup.py",
                 "/%2e%2e/%2e%2e/etc/passwd", "/puckboard/web/server.py", "/admin"):  # fmt: skip
        assert request(view, "GET", path) == 404, path


def test_the_stream_carries_advancing_time():
    episode = Episode("two-robot-pass", seed=0)
    view = watch_episode(episode, port=0, speed=4.0)  # paced, so frames arrive while it runs
    import threading

    runner = threading.Thread(target=episode.run, args=(3.0,), daemon=True)
    try:
        runner.start()
        frames = stream_frames(view, 8)
    finally:
        runner.join(10)
        view.close()
    times = [f["t"] for f in frames]
    assert len(times) == 8 and times == sorted(times) and times[-1] > times[0]


def test_the_same_seed_gives_the_same_run_watched_or_not():
    plain = run_episode("two-robot-pass", seed=3, duration=40.0).to_dict()
    episode = Episode("two-robot-pass", seed=3)
    view = watch_episode(episode, port=0, speed=None)
    try:
        watched = episode.run(40.0).to_dict()
    finally:
        view.close()
    for d in (plain, watched):
        d.pop("wall_s")
        d.pop("realtime_factor")
    assert watched == plain


def test_a_served_world_shows_its_clients_layers_and_judge():
    pytest.importorskip("zmq")
    from puckboard.backends.coppeliasim.server.socket_loop import RemoteApiServer
    from puckboard.scenario.scenefile import load_scene

    server = RemoteApiServer(load_scene("two-robot-pass"), host="127.0.0.1", port=0).start()
    view = watch_server(server, port=0)
    try:
        stopped = wait_for_frame(view, lambda f: True)  # observers run 4x/s when still
        assert stopped["status"] == "stopped" and stopped["t"] == 0.0
        result = run_episode(
            "two-robot-pass", duration=8.0, backend="coppeliasim", port=server.port
        )
        # the observers' next round after the run shows what the clients' sensors were
        # and the timeline so far (a round during the run's first steps, before any
        # layer has driven, shows an empty one: the view refreshes on its own schedule)
        details = wait_for_json(
            view,
            "details.json",
            lambda d: d["left"]["source"] == "served sensors" and d["right"]["timeline"],
        )
    finally:
        view.close()
        server.close()
    assert result.sim_time_s == pytest.approx(8.0, abs=0.06)
    frames = view.follower.frames
    assert frames > 0
    timeline = details["right"]["timeline"]
    assert timeline and timeline[0]["layer"] in {"LineFollow", "Cruise"}  # from the signals


def test_cli_web_errors_are_one_line(monkeypatch, capsys):
    import socket

    from puckboard.cli import main

    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        assert main(["run", "--web", "--web-port", str(port), "--duration", "1"]) == 2
    err = capsys.readouterr().err
    assert "in use" in err and "--web-port" in err and len(err.strip().splitlines()) == 1
    import sys

    monkeypatch.setitem(sys.modules, "aiohttp", None)  # as on a machine without the extra
    monkeypatch.delitem(sys.modules, "puckboard.web.server", raising=False)
    assert main(["run", "--web", "--duration", "1"]) == 2
    assert "pip install 'puckboard[web]'" in capsys.readouterr().err
    assert main(["run", "--speed", "2"]) == 2
    assert "use it with --web" in capsys.readouterr().err


def wait_for_json(view, name: str, ok, timeout: float = 60.0) -> dict:
    """The served view's ``name`` (frame.json, details.json), once ``ok`` holds of it.

    The view's observers refresh it on their own schedule (4x/s when the world stands
    still), so a test waits for what it expects, generously, rather than for a time."""
    deadline = time.monotonic() + timeout
    while True:
        shown = json.loads(get(view.url + name)[1] or b"null")
        if shown is not None and ok(shown):
            return shown
        assert time.monotonic() < deadline, shown
        time.sleep(0.05)


def wait_for_frame(view, ok, timeout: float = 60.0) -> dict:
    """The served view's newest frame, once ``ok(frame)`` holds."""
    return wait_for_json(view, "frame.json", ok, timeout)


def path_length(points) -> float:
    return sum(math.dist(a, b) for a, b in itertools.pairwise(points))


def test_a_restored_served_world_labels_the_previous_run_and_starts_new_trails():
    """After a client's run, sim.stopSimulation puts the robots back at their start: the
    view then shows the scene as restored, a new trail from the start, and the run that
    ended as the *previous* run (its events, verdict and trails), until the next run
    steps, which replaces it."""
    pytest.importorskip("zmq")
    from puckboard.backends.coppeliasim.server.socket_loop import RemoteApiServer
    from puckboard.scenario.scenefile import load_scene

    server = RemoteApiServer(load_scene("two-robot-pass"), host="127.0.0.1", port=0).start()
    view = watch_server(server, port=0)
    try:
        wait_for_frame(view, lambda f: f["status"] == "stopped")
        results, shown = [], []
        for duration in (8.0, 3.0):
            results.append(run_episode(
                "two-robot-pass", duration=duration, backend="coppeliasim", port=server.port
            ))  # fmt: skip
            frame = wait_for_frame(
                view,
                lambda f, d=duration: (
                    (f.get("previous") or {}).get("t") == pytest.approx(d, abs=0.06)
                ),
            )
            shown.append((frame, json.loads(get(view.url + "trails.json")[1])))
    finally:
        view.close()
        server.close()
    for result, (frame, trails) in zip(results, shown):
        assert frame["status"] == "stopped" and frame["t"] == 0.0  # the scene as restored
        assert frame["rtf"] is None  # standing still: no "0.0x real time"
        assert frame["previous"]["t"] == pytest.approx(result.sim_time_s, abs=0.06)
        assert [e["kind"] for e in frame["events"]] == [
            e.kind for e in sorted(result.events, key=lambda e: e.time_s)
        ]  # the run is over when the scene is restored: judged to the end, as the client's
        assert frame["verdict"]["success"] == result.success
        assert frame["verdict"]["failure"] == result.failure
        assert trails["run"] == frame["run"] and trails["previous"]["run"] == frame["run"] - 1
        for robot, metrics in zip(frame["robots"], result.robots):
            current = trails["trails"][robot["name"]]
            assert len(current) <= 1 and all(  # the new trail: nothing but the start
                abs(x - robot["pose"][0]) < 1e-3 and abs(y - robot["pose"][1]) < 1e-3
                for x, y in current
            ), current
            before = trails["previous"]["trails"][robot["name"]]
            # the previous run's trail is that run's path alone (one point each 5 mm)
            assert path_length(before) == pytest.approx(metrics.distance_m, abs=0.02)
        assert trails["previous"]["t"] == frame["previous"]["t"]
    assert [frame["run"] for frame, _ in shown] == [1, 2]  # each restore, a new run
