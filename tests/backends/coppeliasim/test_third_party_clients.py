"""Client programs written for CoppeliaSim, not for puckboard, run against ``puckboard serve``.

Each script in ``clients/`` is a separate process using only the official client, in
the style of CoppeliaSim's own examples and the V-REP-era e-puck scripts (object names,
sensor calls, stepping). The tests check what a user of CoppeliaSim would check: the
robot reaches the goal dummy, the detected points land on the objects whose handles
were returned, the line follower stays on the line, the tree lists the model's parts.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from coppeliasim_support import stop_server

from puckboard.backends.coppeliasim.server.socket_loop import RemoteApiServer
from puckboard.scenario.scenefile import load_scene, parse_scene_text

pytestmark = pytest.mark.network

CLIENTS = Path(__file__).parent / "clients"


def run_client(server: RemoteApiServer, script: str, *args: object) -> dict:
    done = subprocess.run(
        [sys.executable, str(CLIENTS / script), "127.0.0.1", str(server.port), *map(str, args)],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])


def serve(scene) -> RemoteApiServer:
    return RemoteApiServer(scene, host="127.0.0.1", port=0).start()


def scene_from(text: str):
    return parse_scene_text(text, source="test.toml")


GOAL_SCENE = """
name = "goal"
[arena]
xmin = -0.5
ymin = -0.5
xmax = 0.5
ymax = 0.5
[[dummies]]
name = "Goal"
x = 0.3
y = 0.25
[[robots]]
name = "seeker"
x = -0.3
y = -0.3
theta = 0.0
"""


def test_go_to_goal_reaches_the_dummy():
    server = serve(scene_from(GOAL_SCENE))
    try:
        out = run_client(server, "go_to_goal.py")
    finally:
        stop_server(server)
    assert out["reached"], out
    x, y, _ = out["robot"]
    assert math.hypot(x - 0.3, y - 0.25) < 0.025
    assert out["goal"] == pytest.approx([0.3, 0.25, 0.0])


# Robot A at the origin facing +x: another e-puck 20 mm beyond its left side sensor, a
# post 25 mm ahead of its front sensors, a wall 25 mm beyond its right side sensor.
SEEN_SCENE = """
name = "seen"
profile = "epuck-vrep"
[arena]
xmin = -0.3
ymin = -0.06
xmax = 0.3
ymax = 0.3
[[obstacles]]
name = "post"
shape = "circle"
x = 0.0697
y = 0.0
radius = 0.01
[[robots]]
name = "a"
x = 0.0
y = 0.0
theta = 0.0
[[robots]]
name = "b"
x = 0.0
y = 0.09
theta = 0.0
"""


def test_braitenberg_reader_tells_robots_obstacles_and_walls_apart_by_handle():
    scene = scene_from(SEEN_SCENE)
    server = serve(scene)
    try:
        out = run_client(server, "braitenberg_classifier.py", 2)
    finally:
        stop_server(server)
    assert out["seen"] == {"robot": ["/ePuck[1]"], "obstacle": ["/post"], "wall": ["/Wall[0]"]}
    body = 0.0352  # the other robot's body radius (epuck-vrep)
    kinds = set()
    for p in out["points"]:
        x, y, z = p["world"]
        assert z == pytest.approx(0.0332, abs=1e-9)  # on the sensor's plane
        if p["kind"] == "obstacle":
            gap = math.hypot(x - 0.0697, y) - 0.01
        elif p["kind"] == "wall":
            gap = y - (-0.06)
        else:
            gap = math.hypot(x - 0.0, y - 0.09) - body
        # the detected point, taken to the world with the sensor's matrix, lies on the surface
        assert abs(gap) < 1e-3, p
        kinds.add(p["kind"])
    assert kinds == {"robot", "obstacle", "wall"}


def test_line_follower_reading_image_bytes_stays_on_the_line():
    scene = load_scene("line-follow")
    server = serve(scene)
    try:
        out = run_client(server, "light_sensor_line_follower.py", 400)
    finally:
        stop_server(server)
    assert out["resolution"] == [16, 2] and out["bytes"] == 16 * 2 * 3
    assert out["dark_reads"] > 300  # it saw the line nearly all the time
    path = np.array(out["path"])
    seg = scene.track.segments()
    a, v = seg[:, 0], seg[:, 1] - seg[:, 0]
    w = path[:, None, :] - a[None]
    t = np.clip((w * v[None]).sum(-1) / (v * v).sum(-1)[None], 0, 1)
    off = np.linalg.norm(w - t[..., None] * v[None], axis=-1).min(axis=1)
    assert off.max() < 0.015, off.max()  # within a line width of the line, always
    assert np.linalg.norm(np.diff(path, axis=0), axis=1).sum() > 0.6  # and it went somewhere


def test_tree_walk_lists_the_stock_models_parts_and_the_scene():
    server = serve(load_scene("arena"))
    try:
        out = run_client(server, "tree_walk.py")
    finally:
        stop_server(server)
    model = {o["path"]: o for o in out["model"]}
    assert model["/ePuck[0]"]["type"] == "shape"
    assert model["/ePuck[0]/leftJoint"]["type"] == "joint"
    assert model["/ePuck[0]/leftJoint/leftRespondableWheel"]["parent"] == "leftJoint"
    assert model["/ePuck[0]/leftJoint/leftRespondableWheel"]["name"] == "ePuck_leftWheel"
    assert [model[f"/ePuck[0]/proxSensor[{k}]"]["name"] for k in range(8)] == [
        f"ePuck_proxSensor{k + 1}" for k in range(8)
    ]
    assert {model[f"/ePuck[0]/{p}"]["type"] for p in ("lightSensor", "camera")} == {"visionsensor"}
    assert model["/ePuck[0]/ledLight"]["type"] == "light"
    for part in ("base", "bodyElements", "rightJoint", "rightJoint/rightRespondableWheel"):
        assert f"/ePuck[0]/{part}" in model
    scene = {o["path"]: o for o in out["scene"]}
    assert {"/Floor", "/cylinder", "/box", "/Goal", "/ePuck[0]", "/ePuck[1]"} <= set(scene)
    assert [scene[f"/Wall[{k}]"]["name"] for k in range(4)] == ["Wall", "Wall0", "Wall1", "Wall2"]
    assert scene["/Goal"]["type"] == "dummy"
    for obj in out["scene"]:  # parents and children agree
        for child in obj["children"]:
            assert any(o["parent"] == obj["path"].rsplit("/", 1)[-1].split("[")[0]
                       and o["path"].rsplit("/", 1)[-1].split("[")[0] == child
                       for o in out["scene"])  # fmt: skip
