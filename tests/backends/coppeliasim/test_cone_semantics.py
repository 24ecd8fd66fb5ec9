"""The served robot senses as V-REP's e-puck model does: a 30° cone detecting 1.5-41.5 mm."""

from __future__ import annotations

import math

import pytest
import zmq
from coppeliasim_support import stop_server
from coppeliasim_zmqremoteapi_client import RemoteAPIClient

from puckboard.backends.coppeliasim.server.socket_loop import RemoteApiServer
from puckboard.profile import EPUCK_VREP
from puckboard.scenario.scene import CircleObstacle, RobotSpec, Scene

PS0 = 0  # ePuck_proxSensor4 is the physical robot's ps0 (front, right of the axis)
RADIUS = 0.01


def _reading_with_obstacle_at(gap: float, profile: str | None = "epuck-vrep"):
    """readProximitySensor of ePuck_proxSensor4 with a post ``gap`` m in front of it."""
    pose = EPUCK_VREP.prox_poses[PS0]
    reach = gap + RADIUS
    post = CircleObstacle(
        pose.x + reach * math.cos(pose.heading), pose.y + reach * math.sin(pose.heading), RADIUS
    )
    scene = Scene(name="cone", robots=(RobotSpec("a", 0.0, 0.0, 0.0),), obstacles=(post,))
    options = {} if profile == "default" else {"profile": profile}
    server = RemoteApiServer(scene, host="127.0.0.1", port=0, **options).start()
    try:
        client = RemoteAPIClient("127.0.0.1", server.port)
        client.socket.setsockopt(zmq.RCVTIMEO, 5000)
        client.socket.setsockopt(zmq.LINGER, 0)
        sim = client.require("sim")
        sim.setStepping(True)
        sim.startSimulation()
        sim.step()
        result = sim.readProximitySensor(sim.getObject("ePuck_proxSensor4"))
        sim.stopSimulation()
        return result
    finally:
        stop_server(server)


@pytest.mark.parametrize(("gap", "detected"), [(0.001, False), (0.020, True), (0.045, False)])
def test_sensor4_detects_only_between_1_5_and_41_5_mm(gap, detected):
    state, distance, *_ = _reading_with_obstacle_at(gap, profile="default")
    assert bool(state) is detected
    if detected:
        assert distance == pytest.approx(gap, abs=1e-6)  # exact: V-REP's sensors have no noise


def test_the_physical_profile_served_on_request_sees_the_touching_post():
    """With --profile epuck the served robot is the physical one: its IR rays see a post
    1 mm in front of ePuck_proxSensor4's pose, where V-REP's cone is blind."""
    state, distance, *_ = _reading_with_obstacle_at(0.001, profile="epuck")
    assert state == 1 and distance < 0.01
