"""The embedded simulator as a backend: one :class:`EmbeddedAdapter` per simulated robot.

The adapters of one scene share one :class:`~puckboard.sim.world.World`, which is also
their :class:`~puckboard.backends.base.Stepper`: the control loop steps the world once
per cycle, whatever the number of robots. Reading sensors costs no simulation work (the
world computed them when it stepped); the adapter only wraps its robot's rows of the
world's arrays into records, so the engine knows no record type beyond its numbers and
the adapter is the one place where this backend's records are made, as it is for every
other backend.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from ..blackboard import Blackboard, Namespace
from ..records import (
    Acceleration,
    AngularVelocity,
    CameraImage,
    Ground,
    Pose,
    Proximity,
    Sensor,
    WheelEncoders,
    WheelSpeeds,
)
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
        # live read-only views of this robot's rows: reading them costs no copy until a
        # record's constructor makes its own
        self._arrays = world.robot_arrays(index)
        self._builders: dict[Sensor, Callable[[], Any]] = {
            Sensor.PROXIMITY: self._proximity,
            Sensor.GROUND: self._ground,
            Sensor.POSE: self._pose,
            Sensor.ENCODERS: self._encoders,
            Sensor.WHEEL_SPEEDS: self._wheel_speeds,
            Sensor.ACCELERATION: self._acceleration,
            Sensor.GYRO: self._angular_velocity,
        }
        super().__init__(
            name if name is not None else world.robot_names[index],
            profile=world.profiles[index],
            blackboard=blackboard,
            stepper=world,
            command_timeout=command_timeout,
        )

    def sense_all(self) -> dict[Sensor, Any]:
        """Every enabled sensor, as the base class reads them; but on a cycle whose link
        brought no new packet (the scene's ``control.repeated``) nothing is written: the
        blackboard keeps the last records, their age growing, and ``{}`` is returned."""
        if not self.world.fresh_reading(self.index):
            return {}
        return super().sense_all()

    def _read_sensors(self, sensors: frozenset[Sensor]) -> dict[Sensor, Any]:
        """Records of ``sensors`` from the world's latest step (held still while read)."""
        with self.world.lock:
            return self._records(sensors)

    def _records(self, sensors: frozenset[Sensor]) -> dict[Sensor, Any]:
        builders = self._builders
        try:
            return {sensor: builders[sensor]() for sensor in sensors}
        except KeyError as missing:  # the base class asks only for available sensors
            raise ValueError(
                f"the embedded simulator has no {Sensor(missing.args[0]).value} sensor"
            ) from None

    # One builder per sensor, looked up by the sensor (a dict made once per adapter, see
    # __init__) rather than found by a chain of comparisons on every record of every
    # cycle. Array records are given the live views: their constructors copy the values
    # into read-only arrays of their own, so a later step cannot change a record already
    # handed out.
    def _proximity(self) -> Proximity:
        rows = self._arrays
        return Proximity(
            distance=rows.prox_distance, raw=rows.prox_raw, range=self.profile.prox_range
        )

    def _ground(self) -> Ground:
        rows = self._arrays
        return Ground(value=rows.ground, raw=rows.ground_raw)

    def _pose(self) -> Pose:
        x, y, theta = self._arrays.pose.tolist()
        return Pose(x=x, y=y, theta=theta, ground_truth=True)

    def _encoders(self) -> WheelEncoders:
        left, right = self._arrays.encoders.tolist()
        return WheelEncoders(left=left, right=right)

    def _wheel_speeds(self) -> WheelSpeeds:
        left, right = self._arrays.wheel_speeds.tolist()
        return WheelSpeeds(left=left, right=right)

    def _acceleration(self) -> Acceleration:
        ax, ay, az = self._arrays.acceleration.tolist()
        return Acceleration(x=ax, y=ay, z=az)

    def _angular_velocity(self) -> AngularVelocity:
        wx, wy, wz = self._arrays.angular_velocity.tolist()
        return AngularVelocity(x=wx, y=wy, z=wz)

    def _write_wheels(self, left: float, right: float) -> None:
        # clamped once already, by the base class (see RobotAdapter.command_wheels)
        self.world.drive(self.index, left, right)

    def _read_camera(self) -> CameraImage:
        return CameraImage(pixels=self.world.render_camera(self.index))


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
