"""The served functions behave as CoppeliaSim's manual and sources say, call by call."""

from __future__ import annotations

import math
import threading
import time

import numpy as np
import pytest
import zmq
from coppeliasim_support import start_server, stop_server

from puckboard.profile import EPUCK_VREP
from puckboard.records import VREP_ORDER

pytestmark = pytest.mark.network


def _matrix(m12):
    return np.array(m12).reshape(3, 4)


def test_a_coppeliasim_function_we_do_not_serve_is_answered_by_the_server(make_client):
    sim = make_client().require("sim")
    # the attribute exists (the whole sim namespace is listed), so the call reaches us
    with pytest.raises(Exception, match=r"sim\.addDrawingObject is part of CoppeliaSim's API"
                       r" but puckboard serve does not serve it"):  # fmt: skip
        sim.addDrawingObject(sim.drawing_lines, 2, 0, -1, 100)
    assert sim.getSimulationTime() == 0.0


def test_sensors_read_minus_one_until_the_first_step_of_a_run(make_client):
    sim = make_client().require("sim")
    prox = sim.getObject("/ePuck/proxSensor", {"index": 2})
    light = sim.getObject("/ePuck/lightSensor")
    assert sim.readProximitySensor(prox)[0] == -1
    assert sim.readVisionSensor(light) == -1
    sim.setStepping(True)
    sim.startSimulation()
    assert sim.readProximitySensor(prox)[0] == -1  # started, not stepped: not handled yet
    sim.step()
    assert sim.readProximitySensor(prox)[0] in (0, 1)
    state, aux, _ = sim.readVisionSensor(light)
    assert state == 0 and len(aux) == 15  # min, max, mean of intensity, r, g, b, depth
    assert aux[0] <= aux[10] <= aux[5]
    sim.stopSimulation()
    assert sim.readProximitySensor(prox)[0] == -1


def test_frames_are_the_stock_models(make_client):
    sim = make_client().require("sim")
    base = sim.getObject("/ePuck")
    # the base: its origin on the wheel axle, x forward, z up
    x, y, z = sim.getObjectPosition(base, sim.handle_world)
    assert z == pytest.approx(EPUCK_VREP.wheel_radius)
    m = _matrix(sim.getObjectMatrix(base, sim.handle_world))
    np.testing.assert_allclose(m[:, 2], [0, 0, 1], atol=1e-12)
    yaw = sim.getObjectOrientation(base, sim.handle_world)[2]
    np.testing.assert_allclose(m[:, 0], [math.cos(yaw), math.sin(yaw), 0], atol=1e-12)
    for k in range(8):
        sensor = sim.getObject(f"ePuck_proxSensor{k + 1}")
        pose = EPUCK_VREP.prox_poses[VREP_ORDER[k]]
        local = _matrix(sim.getObjectMatrix(sensor, base))
        # z along the direction it looks, on the robot where the model puts it
        np.testing.assert_allclose(
            local[:, 2], [math.cos(pose.heading), math.sin(pose.heading), 0], atol=1e-12
        )
        assert local[:, 3][:2] == pytest.approx([pose.x, pose.y])
        # matrix, quaternion, Euler angles and pose agree
        q = sim.getObjectQuaternion(sensor, sim.handle_world)
        p7 = sim.getObjectPose(sensor, sim.handle_world)
        assert p7[3:] == pytest.approx(q)
        a, b, g = sim.getObjectOrientation(sensor, sim.handle_world)
        rx = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
        ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
        rz = np.array([[math.cos(g), -math.sin(g), 0], [math.sin(g), math.cos(g), 0], [0, 0, 1]])
        world = _matrix(sim.getObjectMatrix(sensor, sim.handle_world))
        np.testing.assert_allclose(rx @ ry @ rz, world[:, :3], atol=1e-9)
    light = _matrix(sim.getObjectMatrix(sim.getObject("/ePuck/lightSensor"), base))
    np.testing.assert_allclose(light[:, 2], [0, 0, -1], atol=1e-12)  # looks down
    assert sim.getObjectParent(sim.getObject("/ePuck/leftRespondableWheel")) == sim.getObject(
        "/ePuck/leftJoint"
    )


def test_velocity_of_a_robot_driving_straight(make_client):
    sim = make_client().require("sim")
    base = sim.getObject("/ePuck")
    for side in ("left", "right"):
        sim.setJointTargetVelocity(sim.getObject(f"/ePuck/{side}Joint"), 2.0)
    sim.setStepping(True)
    sim.startSimulation()
    sim.step()
    linear, angular = sim.getObjectVelocity(base)
    heading = sim.getObjectOrientation(base, sim.handle_world)[2]
    speed = 2.0 * EPUCK_VREP.wheel_radius
    assert linear == pytest.approx(
        [speed * math.cos(heading), speed * math.sin(heading), 0], abs=1e-3
    )
    assert angular == pytest.approx([0, 0, 0], abs=1e-2)
    _, wheel_spin = sim.getObjectVelocity(sim.getObject("/ePuck/leftRespondableWheel"))
    assert np.linalg.norm(wheel_spin) == pytest.approx(2.0, rel=0.05)
    sim.stopSimulation()


def test_signals_are_shared_and_cleared_at_stop(make_client):
    a, b = make_client().require("sim"), make_client().require("sim")
    a.setStringSignal("layer", "avoid")
    a.setInt32Signal("count", 3)
    a.setFloatSignal("gain", 0.5)
    assert (b.getStringSignal("layer"), b.getInt32Signal("count"), b.getFloatSignal("gain")) == (
        "avoid",
        3,
        0.5,
    )
    assert b.getStringSignal("nothing") is None
    assert b.clearInt32Signal("count") == 1 and b.getInt32Signal("count") is None
    b.stopSimulation()
    assert a.getStringSignal("layer") is None and a.getFloatSignal("gain") is None


def test_parameters_and_images(make_client):
    sim = make_client().require("sim")
    light = sim.getObject("ePuck_lightSensor")
    assert sim.getObjectInt32Param(light, sim.visionintparam_resolution_x) == 16
    assert sim.getObjectInt32Param(light, sim.visionintparam_resolution_y) == 2
    sim.setObjectInt32Param(light, sim.objintparam_visibility_layer, 4)
    assert sim.getObjectInt32Param(light, sim.objintparam_visibility_layer) == 4
    with pytest.raises(Exception, match="always velocity-controlled"):
        sim.setObjectInt32Param(
            sim.getObject("/ePuck/leftJoint"), sim.jointintparam_motor_enabled, 0
        )
    assert sim.getInt32Param(sim.intparam_program_version) >= 40700
    sim.setInt32Param(sim.intparam_idle_fps, 0)  # what old examples do: accepted
    rgb, res = sim.getVisionSensorImg(light)
    grey, _ = sim.getVisionSensorImg(light, 1)
    rgba, _ = sim.getVisionSensorImg(light, 2)
    grey_alpha, _ = sim.getVisionSensorImg(light, 3)
    assert res == [16, 2]
    assert (len(rgb), len(grey), len(rgba), len(grey_alpha)) == (96, 32, 128, 64)
    pixels = np.frombuffer(rgb, np.uint8).reshape(-1, 3).astype(int)
    np.testing.assert_array_equal(np.frombuffer(grey, np.uint8), pixels.sum(axis=1) // 3)
    window, res = sim.getVisionSensorImg(light, 0, 0.0, [2, 1], [4, 1])
    assert len(window) == 12 and res == [16, 2]  # the sensor's resolution, as CoppeliaSim


def test_visual_only_parameters_are_accepted_with_no_effect(make_client):
    """What real clients call to tidy CoppeliaSim's view (hide the IR rays, colour the
    hierarchy, place the camera's window) succeeds, as there, and changes nothing sensed."""
    sim = make_client().require("sim")
    sensors = [sim.getObject("/ePuck/proxSensor", {"index": k}) for k in range(8)]
    joint = sim.getObject("/ePuck/leftJoint")
    camera = sim.getObject("/ePuck/camera")
    sim.setStepping(True)
    sim.startSimulation()
    sim.step()
    before = [sim.readProximitySensor(s) for s in sensors]
    for s in sensors:
        assert sim.setObjectInt32Param(s, sim.proxintparam_ray_invisibility, 1) is None
    sim.setObjectInt32Param(sim.getObject("/ePuck"), sim.objintparam_hierarchycolor, 2)
    sim.setObjectInt32Param(camera, sim.visionintparam_windowed_size_x, 320)
    sim.setObjectInt32Param(camera, sim.visionintparam_windowed_pos_y, 40)
    # a wheel motor's own settings: nothing changes, as in CoppeliaSim
    sim.setObjectInt32Param(joint, sim.jointintparam_motor_enabled, 1)
    sim.setObjectInt32Param(joint, sim.jointintparam_ctrl_enabled, 0)
    sim.setObjectInt32Param(joint, sim.jointintparam_dynctrlmode, sim.jointdynctrl_velocity)
    assert [sim.readProximitySensor(s) for s in sensors] == before
    sim.setObjectInt32Param(camera, sim.objintparam_visibility_layer, 70000)
    assert sim.getObjectInt32Param(camera, sim.objintparam_visibility_layer) == 65535
    sim.stopSimulation()


# (object, its kind as a refusal names it, a parameter of that kind it cannot set)
_KINDS = [
    ("/ePuck", "a shape", "shapeintparam_respondable"),
    ("/Floor", "a shape", "shapeintparam_static"),
    ("/ePuck/leftJoint", "a joint", "jointintparam_ctrl_enabled"),
    ("/ePuck/proxSensor", "a proximity sensor", "proxintparam_volume_type"),
    ("/ePuck/lightSensor", "a vision sensor", "visionintparam_resolution_x"),
    ("/ePuck/ledLight", "a light", "lightintparam_pov_casts_shadows"),
    ("/Goal", "a dummy", "dummyintparam_follow_path"),
]


def test_every_parameter_refusal_names_the_objects_own_kind():
    """A proximity sensor is not a joint: each refusal says what the object is, and only
    a joint's mentions wheels."""
    from coppeliasim_zmqremoteapi_client import RemoteAPIClient

    srv = start_server("arena")
    client = RemoteAPIClient("127.0.0.1", srv.port)
    try:
        client.socket.setsockopt(zmq.RCVTIMEO, 5000)
        client.socket.setsockopt(zmq.LINGER, 0)
        sim = client.require("sim")
        for path, kind, own in _KINDS:
            handle = sim.getObject(path)
            name = sim.getObjectName(handle)
            value = 1 if own != "jointintparam_ctrl_enabled" else 8
            for func, args, wheels in (
                (sim.setObjectInt32Param, (handle, getattr(sim, own), value), kind == "a joint"),
                (sim.getObjectInt32Param, (handle, sim.proxintparam_entity_to_detect), False),
            ):
                with pytest.raises(Exception) as refused:
                    func(*args)
                message = str(refused.value)
                assert f"{name} ({kind})" in message, message
                assert ("wheel" in message) == wheels, message
            # another kind's parameter: said to be that kind's, and what this object is
            if kind != "a joint":
                with pytest.raises(Exception) as refused:
                    sim.setObjectInt32Param(handle, sim.jointintparam_motor_enabled, 0)
                assert f"it is a joint's parameter, and {name} is {kind}" in str(refused.value)
                assert "wheel" not in str(refused.value)
        prox = sim.getObject("/ePuck/proxSensor")
        with pytest.raises(Exception, match=r"\(a proximity sensor\) cannot be moved: it is part"):
            sim.setObjectPosition(prox, [0.0, 0.0, 0.0])
        with pytest.raises(Exception, match=r"Floor \(a shape\) cannot be moved: puckboard"):
            sim.setObjectPosition(sim.getObject("/Floor"), [0.0, 0.0, 0.0])
        with pytest.raises(Exception, match=r"\(a proximity sensor\) has no child script"):
            sim.getScript(sim.scripttype_childscript, prox)
        with pytest.raises(Exception, match="is a joint, not a proximity sensor"):
            sim.readProximitySensor(sim.getObject("/ePuck/leftJoint"))
        with pytest.raises(Exception, match="is a proximity sensor, not a vision sensor"):
            sim.getVisionSensorRes(prox)
    finally:
        client.socket.close(0)
        stop_server(srv)


def test_dummies_move_and_robots_do_not():
    srv = start_server("arena")
    try:
        from coppeliasim_zmqremoteapi_client import RemoteAPIClient

        client = RemoteAPIClient("127.0.0.1", srv.port)
        client.socket.setsockopt(zmq.RCVTIMEO, 5000)
        sim = client.require("sim")
        goal = sim.getObject("/Goal")
        sim.setObjectPosition(goal, [0.1, -0.2, 0.0])
        assert sim.getObjectPosition(goal, sim.handle_world) == pytest.approx([0.1, -0.2, 0.0])
        sim.setObjectPosition(goal, sim.handle_world, [0.2, 0.2, 0.0])  # pre-4.5 order
        assert sim.getObjectPosition(goal, sim.handle_world) == pytest.approx([0.2, 0.2, 0.0])
        with pytest.raises(Exception, match="the served robot ePuck, which moves only through"):
            sim.setObjectPosition(sim.getObject("/ePuck"), [0.0, 0.0, 0.0])
        sim.stopSimulation()  # restores the scene, dummies included
        assert sim.getObjectPosition(goal, sim.handle_world) == pytest.approx([0.35, 0.25, 0.0])
        client.socket.close(0)
    finally:
        stop_server(srv)


def test_alias_options(make_client):
    sim = make_client().require("sim")
    wheel = sim.getObject("ePuck_leftWheel#0")
    assert sim.getObjectAlias(wheel) == "leftRespondableWheel"
    assert sim.getObjectAlias(wheel, 1) == "/ePuck[1]/leftRespondableWheel"
    assert sim.getObjectAlias(wheel, 2) == "/ePuck[1]/leftJoint/leftRespondableWheel"
    assert sim.getObjectAlias(wheel, 4) == f"leftRespondableWheel__{wheel}__"
    assert sim.getObjectAlias(sim.getObject("/ePuck[1]/proxSensor[2]"), 0) == "proxSensor[2]"
    assert sim.getObjectName(wheel) == "ePuck_leftWheel#0"


def test_step_without_stepping_waits_for_the_next_simulation_step(make_client):
    sim = make_client().require("sim")
    sim.startSimulation()  # free-running, in real time
    for _ in range(3):
        before = sim.getSimulationTime()
        sim.step()
        assert sim.getSimulationTime() > before
    sim.stopSimulation()
    sim.step()  # stopped: nothing to wait for


def test_a_silent_stepping_client_holds_the_others_until_its_idle_timeout():
    """As in CoppeliaSim: no stepping timeout by default, the idle timeout decides."""
    from coppeliasim_zmqremoteapi_client import RemoteAPIClient

    srv = start_server(max_idle=1.0)
    clients = []
    try:
        silent = RemoteAPIClient("127.0.0.1", srv.port)
        live = RemoteAPIClient("127.0.0.1", srv.port)
        clients = [silent, live]
        for c in clients:
            c.socket.setsockopt(zmq.LINGER, 0)
        live.socket.setsockopt(zmq.RCVTIMEO, 10000)
        silent.call("sim.setStepping", [True])
        live.call("sim.setStepping", [True])
        live.call("sim.startSimulation", [])
        started = time.monotonic()
        done = threading.Event()

        def step() -> None:
            live.call("sim.step", [])
            done.set()

        threading.Thread(target=step, daemon=True).start()
        assert not done.wait(0.5)  # held by the silent client ...
        assert done.wait(8.0)  # ... until it is forgotten
        assert time.monotonic() - started >= 0.9
    finally:
        for c in clients:
            c.socket.close(0)
        stop_server(srv)
