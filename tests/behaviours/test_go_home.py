"""GoHome: a layer that steers by the odometry estimate and knows when not to."""

from __future__ import annotations

import math

import numpy as np
import pytest

from puckboard.backends.fake import FakeAdapter, FakeClock
from puckboard.behaviours import Controller, Cruise, GoHome
from puckboard.blackboard import Blackboard
from puckboard.control.loop import ControlLoop
from puckboard.estimation import OdometryNoise, OdometrySource


def _run(go_home: GoHome, cycles: int, noise: OdometryNoise | None = None):
    clock = FakeClock(dt=0.05)
    board = Blackboard(clock=lambda: clock.time)
    robot = FakeAdapter("epuck", blackboard=board, clock=clock, pose=(0.2, 0.1, 0.5))

    # drive an arc first, so home is behind and to the side
    class Arc(Cruise):
        def command(self, frame):
            from puckboard.records import WheelCommand

            return WheelCommand(3.0, 4.0)

    loop = ControlLoop([(robot, Controller([go_home, Arc()]))])
    OdometrySource(noise=noise).attach(loop)
    loop.run(cycles=cycles, close=False)
    return robot, board, loop


def test_go_home_returns_to_the_start_and_stays():
    layer = GoHome(after=3.0, tolerance=0.01)
    robot, board, loop = _run(layer, 600)
    assert layer.arrived
    # the fake robot has perfect kinematics: the estimate's home is the true start
    assert math.hypot(robot.x - 0.2, robot.y - 0.1) < 0.015
    assert board.value("epuck/command/layer") == "GoHome"
    assert robot.wheels == (0.0, 0.0)
    loop.close()


def test_go_home_waits_for_its_time():
    layer = GoHome(after=100.0)
    robot, board, loop = _run(layer, 20)
    assert board.value("epuck/command/layer") == "Arc"
    loop.close()


def test_go_home_gives_up_when_the_estimate_is_too_uncertain():
    layer = GoHome(after=2.0, max_sd=0.005)
    robot, board, loop = _run(layer, 200, noise=OdometryNoise(travel_variance=1e-4))
    cov = board.value("epuck/estimate/pose_cov")
    assert math.sqrt(cov[0, 0] + cov[1, 1]) > 0.005
    assert board.value("epuck/command/layer") == "Arc"  # the lower layer took over again
    loop.close()


def test_go_home_refuses_bad_parameters():
    with pytest.raises(ValueError, match="tolerance"):
        GoHome(tolerance=0.0)
    assert np.isinf(GoHome().max_sd)
