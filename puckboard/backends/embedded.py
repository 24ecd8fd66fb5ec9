"""The embedded simulator as a backend: one :class:`EmbeddedAdapter` per simulated robot.

The adapters of one scene share one :class:`~puckboard.sim.world.World`, which is also
their :class:`~puckboard.backends.base.Stepper`: the control loop steps the world once
per cycle, whatever the number of robots. Reading sensors costs no simulation work (the
world computed them when it stepped); the adapter only wraps arrays into records.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ..blackboard import Blackboard, Namespace
from ..records import CameraImage, Sensor
from .base import Connection, RobotAdapter

if TYPE_CHECKING:
    from ..scenario.scene import Scene
    from ..sim.world import World

__all__ = ["EmbeddedAdapter", "open_embedded"]


class EmbeddedAdapter(RobotAdapter):
    """Robot ``index`` of a :class:`~puckboard.sim.world.World`."""

    backend_name = "embedded"
    #: No light sources are modelled, so there is no ambient-light sensor.
    available_sensors = frozenset(Sensor) - {Sensor.LIGHT}
    #: The gyro is there (``adapter.enable("gyro")``) but off by default: no shipped
    #: controller reads it, and a record per robot per cycle costs the simulator's speed
    #: (docs/simulator.md gives the measured cost).
    opt_in_sensors = frozenset({Sensor.CAMERA, Sensor.GYRO})

    def __init__(
        self,
        world: World,
        index: int,
        *,
        name: str | None = None,
        blackboard: Blackboard | Namespace | None = None,
        command_timeout: float | None = None,
    ) -> None:
        if not 0 <= index < len(world.robot_names):
            raise IndexError(
                f"robot index {index} out of range; the world has {len(world.robot_names)} robots"
            )
        self.world = world
        self.index = index
        super().__init__(
            name if name is not None else world.robot_names[index],
            profile=world.profiles[index],
            blackboard=blackboard,
            stepper=world,
            command_timeout=command_timeout,
        )

    def _read_sensors(self, sensors: frozenset[Sensor]) -> dict[Sensor, Any]:
        return self.world.read(self.index, sensors)

    def _write_wheels(self, left: float, right: float) -> None:
        self.world.set_wheel_speeds(self.index, left, right)

    def _read_camera(self) -> CameraImage:
        return self.world.camera(self.index)


def open_embedded(
    scene: Scene | str,
    *,
    seed: int = 0,
    blackboard: Blackboard | None = None,
    command_timeout: float | None = None,
    **world_options: Any,
) -> Connection:
    """Build a world for ``scene`` (a Scene, a shipped scene name or a scene file path).

    Returns a :class:`~puckboard.backends.base.Connection` with one adapter per robot
    (namespace = robot name), the world as both ``stepper`` and ``world``, and a
    blackboard whose clock is simulation time. ``world_options`` go to
    :class:`~puckboard.sim.world.World` (``ir_rays``, ``ground_footprint``).
    """
    from ..sim.world import World

    if isinstance(scene, str):
        from ..scenario.scenefile import load_scene

        scene = load_scene(scene)
    world = World(scene, seed=seed, **world_options)
    board = blackboard if blackboard is not None else Blackboard(clock=lambda: world.time)
    adapters: dict[str, RobotAdapter] = {}
    for i, name in enumerate(world.robot_names):
        adapters[name] = EmbeddedAdapter(
            world, i, blackboard=board, command_timeout=command_timeout
        )
    world.start()
    return Connection(adapters=adapters, blackboard=board, stepper=world, world=world)
