"""A small stand-in for :class:`puckboard.control.episode.Episode` built on the fake adapter.

It has the attributes the visual tools use (``scene``, ``blackboard``, ``controllers``,
``connection.adapters``, ``loop``, ``world``, observers) and nothing else, so the tools
are tested against the contract rather than one backend.
"""

from __future__ import annotations

import math

from puckboard.backends.base import Connection
from puckboard.backends.fake import FakeAdapter, FakeClock
from puckboard.behaviours import load_controller
from puckboard.blackboard import Blackboard
from puckboard.control.loop import ControlLoop
from puckboard.records import Sensor
from puckboard.scenario.scene import Arena, CircleObstacle, RobotSpec, Scene, Track


def stand_in_scene() -> Scene:
    angles = [2 * math.pi * k / 24 for k in range(24)]
    return Scene(
        name="stand-in",
        robots=(
            RobotSpec("red", 0.4, 0.0, math.pi / 2, colour=(200, 40, 40)),
            RobotSpec("blue", -0.4, 0.0, -math.pi / 2, colour=(40, 80, 200)),
        ),
        track=Track([(0.4 * math.cos(a), 0.4 * math.sin(a)) for a in angles], width=0.02),
        obstacles=(CircleObstacle(0.0, 0.4, 0.03, name="A"),),
        arena=Arena(-0.6, -0.6, 0.6, 0.6),
        dt=0.05,
        duration=4.0,
    )


class StandInEpisode:
    def __init__(self, scene: Scene | None = None, *, controller: str = "improved", seed: int = 0):
        self.scene = scene or stand_in_scene()
        self.seed = seed
        self.backend = "fake"
        clock = FakeClock(self.scene.dt)
        board = Blackboard(clock=lambda: clock.time)
        adapters = {}
        for spec in self.scene.robots:
            a = FakeAdapter(
                spec.name, blackboard=board, clock=clock, pose=(spec.x, spec.y, spec.theta)
            )
            a.enable(Sensor.POSE, Sensor.PROXIMITY, Sensor.GROUND)
            adapters[spec.name] = a
        adapters["red"].set_proximity(front_left=0.03, diagonal_left=0.045)
        adapters["blue"].set_ground(centre=0.1)
        self.connection = Connection(adapters, board, clock)
        self.blackboard = board
        self.world = None
        self.controllers = {name: load_controller(controller) for name in adapters}
        self.loop = ControlLoop([(adapters[n], self.controllers[n]) for n in adapters])

    def add_observer(self, fn):
        self.loop.add_observer(lambda _loop: fn(self))

    def add_close_observer(self, fn):
        self.loop.add_close_observer(lambda _loop: fn(self))

    def run(self, duration=None):
        self.loop.run(duration if duration is not None else self.scene.duration)
        return self
