"""The wire protocol, driven by the official client exactly as a user's script would."""

from __future__ import annotations

import math
import subprocess
import sys
import threading
import uuid

import cbor2
import numpy as np
import pytest
import zmq
from coppeliasim_support import start_server, stop_server

from puckboard.backends.coppeliasim.server.objects import SceneObjects
from puckboard.profile import EPUCK2
from puckboard.records import VREP_ORDER
from puckboard.scenario.scenefile import load_scene
from puckboard.sim.world import World

pytestmark = pytest.mark.network


def raw_request(port: int, message: dict | bytes) -> dict:
    """One request on a fresh REQ socket; the decoded reply."""
    ctx = zmq.Context.instance()
    sock = ctx.socket(zmq.REQ)
    sock.setsockopt(zmq.LINGER, 0)
    sock.setsockopt(zmq.RCVTIMEO, 5000)
    sock.connect(f"tcp://127.0.0.1:{port}")
    try:
        sock.send(message if isinstance(message, bytes) else cbor2.dumps(message))
        return cbor2.loads(sock.recv())
    finally:
        sock.close(0)


def test_discovery_lists_coppeliasims_whole_sim_namespace(server, make_client):
    client = make_client()
    sim = client.require("sim")
    info = client.call("zmqRemoteApi.info", ["sim"])
    functions = {k for k, v in info.items() if "func" in v}
    served = {name.removeprefix("sim.") for name in server.api.functions}
    assert {"getObject", "setJointTargetVelocity", "readProximitySensor", "step"} <= served
    assert served <= functions
    # CoppeliaSim's names we do not serve are listed too, so they reach the server
    assert {"addDrawingObject", "checkCollision", "getShapeColor"} <= functions - served
    assert len(functions) > 400
    assert sim.handle_world == -1
    assert isinstance(sim.simulation_stopped, int)
    assert sim.getSimulationState() == sim.simulation_stopped


def test_names_and_alias_paths_resolve_to_the_same_objects(server, make_client):
    sim = make_client().require("sim")
    assert sim.getObject("ePuck") == sim.getObject("/ePuck") == sim.getObject("/ePuck[0]")
    assert sim.getObject("ePuck#0") == sim.getObject("/ePuck[1]") == sim.getObject("/ePuck{1}")
    assert sim.getObject("ePuck_leftJoint#0") == sim.getObject("/ePuck[1]/leftJoint")
    for k in range(8):
        assert sim.getObject(f"ePuck_proxSensor{k + 1}#0") == sim.getObject(
            "/ePuck[1]/proxSensor", {"index": k}
        ) == sim.getObject(f"/ePuck[1]/proxSensor[{k}]")  # fmt: skip
    assert sim.getObject("/ePuck[7]", {"noError": True}) == -1
    assert sim.getObjectAlias(sim.getObject("ePuck_camera#0"), 1) == "/ePuck[1]/camera"


def test_unknown_function_answers_an_error_naming_it(server, make_client):
    client = make_client()
    with pytest.raises(
        Exception, match=r"No such function: sim\.getObjectPositon.*getObjectPosition"
    ):
        client.call("sim.getObjectPositon", [1, -1])
    with pytest.raises(Exception, match="No such function: os.system"):
        client.call("os.system", ["true"])
    assert client.call("sim.getSimulationTime", []) == 0.0  # still served afterwards


def test_bad_arguments_are_refused_with_the_parameter_named(server, make_client):
    sim = make_client().require("sim")
    joint = sim.getObject("/ePuck/leftJoint")
    with pytest.raises(Exception, match=r"bad argument #2 .*targetVelocity: number expected"):
        sim.setJointTargetVelocity(joint, "fast")
    with pytest.raises(Exception, match=r"bad argument #1 .*objectPath: string expected"):
        sim.getObject(42)
    with pytest.raises(Exception, match="is a proximity sensor, not a joint"):
        sim.setJointTargetVelocity(sim.getObject("ePuck_proxSensor1"), 1.0)
    with pytest.raises(Exception, match=r"object does not exist \(handle 99999\)"):
        sim.getJointPosition(99999)
    with pytest.raises(
        Exception, match="object does not exist, or alias/path is ill formatted: '/ePuk'.*ePuck#0"
    ):
        sim.getObject("/ePuk")


def test_protocol_edges(server):
    # a protocol-1 client (no uuid) gets CoppeliaSim's version message, in both formats
    reply = raw_request(server.port, {"func": "sim.getSimulationTime", "args": []})
    assert reply["success"] is False and "version" in reply["error"] and "err" in reply
    # the Lua escape hatch of the real server is not served
    reply = raw_request(server.port, {"eval": "os.exit()", "uuid": "x"})
    assert "not served" in reply["err"]
    # argsL restores trailing nils: getObject(path, nil) is getObject(path)
    reply = raw_request(
        server.port, {"func": "sim.getObject", "args": ["/ePuck"], "argsL": 2, "uuid": "y"}
    )
    assert reply["ret"][0] > 0
    reply = raw_request(server.port, {"func": "_*end*_", "args": [], "uuid": "y"})
    assert reply == {}
    reply = raw_request(
        server.port, {"func": "zmqRemoteApi.require", "args": ["simIK"], "uuid": "z"}
    )
    assert "not served" in reply["err"]


def test_sensor_functions_return_what_the_world_computed(server, make_client):
    sim = make_client().require("sim")
    world = World(load_scene("two-robot-pass"), seed=0)
    sim.setStepping(True)
    sim.startSimulation()
    left, right = sim.getObject("/ePuck[1]/leftJoint"), sim.getObject("/ePuck[1]/rightJoint")
    sim.setJointTargetVelocity(left, 4.0)
    sim.setJointTargetVelocity(right, 3.0)
    world.set_wheel_speeds(1, 4.0, 3.0)
    for _ in range(30):
        sim.step()
    world.step(30)
    assert sim.getSimulationTime() == pytest.approx(world.time)
    x, y, _ = sim.getObjectPosition(sim.getObject("/ePuck[1]"), sim.handle_world)
    assert (x, y) == pytest.approx(tuple(world.poses[1, :2]))
    yaw = sim.getObjectOrientation(sim.getObject("/ePuck[1]"), -1)[2]
    assert yaw == pytest.approx(world.poses[1, 2])
    angle = sim.getJointPosition(left)
    assert -math.pi <= angle <= math.pi
    assert angle == pytest.approx(math.remainder(world.encoders[1, 0], math.tau))
    assert sim.getJointVelocity(right) == pytest.approx(world.wheel_speeds[1, 1])
    for k in range(8):
        res, dist, *_ = sim.readProximitySensor(sim.getObject(f"ePuck_proxSensor{k + 1}#0"))
        expected = world.prox_distance[1, VREP_ORDER[k]]
        assert res == int(expected < 0.05)
        if res:
            assert dist == pytest.approx(expected)
    image, (w, h) = sim.getVisionSensorImg(sim.getObject("/ePuck[1]/camera"))
    assert (w, h) == tuple(load_scene("two-robot-pass").camera_size)
    frame = np.frombuffer(image, np.uint8).reshape(h, w, 3)
    np.testing.assert_array_equal(frame, world.render_camera(1)[::-1])  # bottom row first
    grey, res = sim.getVisionSensorImg(sim.getObject("/ePuck[1]/lightSensor"), 1)
    assert res == [16, 2]  # the stock model's light sensor
    stock = np.frombuffer(grey, np.uint8)[[0, 7, 31]]  # where the stock script reads it
    np.testing.assert_allclose(stock / 255, world.ground[1], atol=0.5 / 255)


def test_stepping_waits_for_every_stepping_client(server, make_client):
    """Two stepping clients: the first one's sim.step returns only once the second stepped."""
    a, b, observer = make_client(), make_client(), make_client()
    sim_a, sim_b, sim_o = a.require("sim"), b.require("sim"), observer.require("sim")
    assert sim_a.setStepping(True) == 0
    assert sim_b.setStepping(True) == 0
    sim_a.startSimulation()
    dt = sim_o.getSimulationTimeStep()
    done = threading.Event()

    def step_a() -> None:
        sim_a.step()  # the server answers _*wait*_; the client answers _*executed*_ ...
        done.set()

    thread = threading.Thread(target=step_a, daemon=True)
    thread.start()
    assert not done.wait(0.5)  # ... and a keeps waiting: b has not stepped
    assert sim_o.getSimulationTime() == 0.0
    sim_b.step()
    assert done.wait(5.0)
    thread.join(5.0)
    assert sim_o.getSimulationTime() == pytest.approx(dt)  # exactly one step for both
    sim_b.setStepping(False)
    sim_a.step()  # alone now: no waiting
    assert sim_o.getSimulationTime() == pytest.approx(2 * dt)
    sim_o.stopSimulation()
    assert sim_o.getSimulationTime() == 0.0  # the scene is restored


def test_a_waiting_client_gets_heartbeats_not_silence():
    """While held back, a client sees _*wait*_ replies often enough for a short timeout."""
    from coppeliasim_zmqremoteapi_client import RemoteAPIClient

    srv = start_server(heartbeat=0.05)
    clients = [RemoteAPIClient("127.0.0.1", srv.port) for _ in range(2)]
    try:
        for c in clients:
            c.socket.setsockopt(zmq.LINGER, 0)
            c.socket.setsockopt(zmq.RCVTIMEO, 500)  # 10 heartbeats
        a, b = clients
        a.call("sim.setStepping", [True])
        b.call("sim.setStepping", [True])
        a.call("sim.startSimulation", [])
        errors: list[BaseException] = []

        def step_a() -> None:
            try:
                a.call("sim.step", [])
            except BaseException as exc:  # zmq.Again here would mean silence
                errors.append(exc)

        thread = threading.Thread(target=step_a, daemon=True)
        thread.start()
        thread.join(1.5)  # three times the client's receive timeout
        assert thread.is_alive() and not errors
        b.call("sim.step", [])
        thread.join(5.0)
        assert not thread.is_alive() and not errors
    finally:
        for c in clients:
            c.socket.close(0)
        stop_server(srv)


def test_a_vanished_stepping_client_stops_holding_the_simulation_back():
    from coppeliasim_zmqremoteapi_client import RemoteAPIClient

    srv = start_server(stepping_timeout=0.3)
    try:
        gone = RemoteAPIClient("127.0.0.1", srv.port)
        gone.socket.setsockopt(zmq.LINGER, 0)
        gone.call("sim.setStepping", [True])
        gone.call(
            "sim.setJointTargetVelocity", [gone.call("sim.getObject", ["/ePuck/leftJoint"]), 2.0]
        )
        gone.socket.close(0)  # crashes without a word
        live = RemoteAPIClient("127.0.0.1", srv.port)
        live.socket.setsockopt(zmq.RCVTIMEO, 5000)
        live.call("sim.setStepping", [True])
        live.call("sim.startSimulation", [])
        live.call("sim.step", [])  # returns once the silent client no longer gates
        assert live.call("sim.getSimulationTime", []) > 0
        live.socket.close(0)
    finally:
        stop_server(srv)


def test_scene_objects_name_every_part_of_every_robot():
    objects = SceneObjects([EPUCK2] * 3)
    names = {o.name for o in objects}
    for suffix in ("", "#0", "#1"):
        assert f"ePuck{suffix}" in names
        assert f"ePuck_rightJoint{suffix}" in names
        assert {f"ePuck_proxSensor{k}{suffix}" for k in range(1, 9)} <= names
        assert f"ePuck_lightSensor{suffix}" in names and f"ePuck_camera{suffix}" in names
    assert objects.resolve("/ePuck[2]/camera").name == "ePuck_camera#1"
    with pytest.raises(LookupError, match="needs a script"):
        objects.resolve("./leftJoint")
    assert len({o.handle for o in objects}) == len(objects)


def test_new_uuid_is_a_new_client(server):
    for _ in range(3):
        raw_request(
            server.port, {"func": "sim.getSimulationTime", "args": [], "uuid": str(uuid.uuid4())}
        )
    assert len(server.clients) >= 3


def test_a_forgotten_client_has_its_robot_stopped():
    """A client silent beyond its idle timeout is forgotten and the wheels it set go to 0."""
    import time

    from coppeliasim_zmqremoteapi_client import RemoteAPIClient

    srv = start_server(max_idle=0.2)
    client = RemoteAPIClient("127.0.0.1", srv.port)
    try:
        client.socket.setsockopt(zmq.LINGER, 0)
        client.socket.setsockopt(zmq.RCVTIMEO, 5000)
        joint = client.call("sim.getObject", ["/ePuck[1]/rightJoint"])
        client.call("sim.setJointTargetVelocity", [joint, 3.0])
        assert srv.api.targets[1, 1] == 3.0
        deadline = time.monotonic() + 5.0
        while len(srv.clients) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert len(srv.clients) == 0
        assert srv.api.targets[1].tolist() == [0.0, 0.0]
    finally:
        client.socket.close(0)
        stop_server(srv)


def test_docs_table_lists_exactly_the_served_functions():
    import re
    from pathlib import Path

    from puckboard.backends.coppeliasim.server.simapi import SimApi

    text = (Path(__file__).parents[3] / "docs" / "coppeliasim.md").read_text(encoding="utf-8")
    section = text.split("### Every served function", 1)[1].split("\n## ", 1)[0]
    rows = [line.split("|")[1] for line in section.splitlines() if line.startswith("| `sim.")]
    documented = {m for row in rows for m in re.findall(r"`(sim\.[A-Za-z0-9]+)", row)}
    served = set(SimApi(load_scene("two-robot-pass")).functions)
    assert documented == served, (served - documented, documented - served)


def test_serve_lists_its_functions_and_checks_its_timeouts():
    done = subprocess.run(
        [sys.executable, "-m", "puckboard", "serve", "--functions"],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert done.returncode == 0
    listed = done.stdout.split()
    assert "sim.readProximitySensor" in listed and "sim.getObjectsInTree" in listed
    assert "docs/coppeliasim.md" in done.stderr
    for option in ("--idle-timeout", "--stepping-timeout"):
        bad = subprocess.run(
            [sys.executable, "-m", "puckboard", "serve", option, "0"],
            capture_output=True, text=True, timeout=60,
        )  # fmt: skip
        assert bad.returncode == 2
        assert f"{option} must be a finite positive number of seconds" in bad.stderr
