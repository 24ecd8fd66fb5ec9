"""A fake robot that ships with the package, for tests, notebooks and first steps.

Like gpiozero's mock pin factory: no simulator, no robot, yet every call of the adapter
contract works. The robot integrates its pose from the commanded wheel speeds (perfect
kinematics, no obstacles) and reports whatever sensor readings you set, so you can put a
controller in front of a situation you describe::

    fake = FakeAdapter()
    fake.set_proximity(front_left=0.02)        # something 2 cm ahead on the left
    fake.set_ground(left=0.1)                  # the line under the left ground sensor
    ...

A :class:`FakeAdapter` can also replay recorded readings: pass ``replay``, a sequence of
``{sensor: record}`` dicts, and each ``sense_all`` returns the next one.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from ..blackboard import Blackboard, Namespace
from ..ir_response import calibrated_from_distance
from ..profile import EPUCK2, RobotProfile
from ..records import (
    GRAVITY,
    GROUND_NAMES,
    PROX_NAMES,
    Acceleration,
    AngularVelocity,
    CameraImage,
    Ground,
    Light,
    Pose,
    Proximity,
    Sensor,
    WheelEncoders,
    WheelSpeeds,
)
from .base import Connection, RobotAdapter, Stepper

if TYPE_CHECKING:
    from ..scenario.scene import Scene

__all__ = ["FakeAdapter", "FakeClock", "open_fake"]


class FakeClock(Stepper):
    """A stepper that only advances time and integrates its robots' kinematics."""

    def __init__(self, dt: float = 0.05) -> None:
        if dt <= 0:
            raise ValueError(f"dt must be positive seconds, got {dt}")
        self._dt = dt
        self._time = 0.0
        self._running = False
        self.robots: list[FakeAdapter] = []

    @property
    def dt(self) -> float:
        return self._dt

    @property
    def time(self) -> float:
        return self._time

    def start(self) -> None:
        self._running = True

    def step(self, n: int = 1) -> None:
        for _ in range(n):
            for robot in self.robots:
                robot._integrate(self._dt)
            self._time += self._dt

    def stop(self) -> None:
        self._running = False


class FakeAdapter(RobotAdapter):
    """A robot with settable sensors and ideal kinematics; see the module docstring.

    ``profile`` is what the robot believes it is (its adapter's profile); ``actual``, when
    given, is what it is as built (a drawn plausible robot): its pose integrates with
    ``actual``'s wheels and axle, while its encoders follow the command.
    """

    backend_name = "fake"

    def __init__(
        self,
        name: str = "epuck",
        *,
        profile: RobotProfile = EPUCK2,
        blackboard: Blackboard | Namespace | None = None,
        clock: FakeClock | None = None,
        pose: tuple[float, float, float] = (0.0, 0.0, 0.0),
        replay: Iterable[Mapping[Sensor, Any]] | None = None,
        command_timeout: float | None = None,
        actual: RobotProfile | None = None,
    ) -> None:
        self.actual = actual if actual is not None else profile
        self.clock = clock if clock is not None else FakeClock()
        self.clock.robots.append(self)
        super().__init__(
            name,
            profile=profile,
            blackboard=blackboard,
            stepper=self.clock,
            command_timeout=command_timeout,
        )
        self.x, self.y, self.theta = pose
        self.encoders = [0.0, 0.0]
        self.wheels = (0.0, 0.0)
        self.commands: list[tuple[float, float, float]] = []  # (time, left, right) sent
        self._prox = Proximity.nothing(profile.prox_range)
        self._ground = Ground(np.ones(3), np.full(3, 1000.0))
        self._image = CameraImage(np.full((39, 52, 3), 200, dtype=np.uint8))
        self._replay = iter(replay) if replay is not None else None

    # -- scripting the world ---------------------------------------------------------------
    def set_proximity(self, **distances: float) -> None:
        """Set obstacle distances (m) by sensor name; unnamed sensors see nothing."""
        rng = self.profile.prox_range
        d = np.full(8, rng)
        for name, value in distances.items():
            if name not in PROX_NAMES:
                raise ValueError(
                    f"unknown proximity sensor {name!r}; names: {', '.join(PROX_NAMES)}"
                )
            distance = float(value)
            if not (math.isfinite(distance) and distance >= 0):  # not clamped: a typo
                raise ValueError(
                    f"set_proximity({name}={value!r}): a distance must be a finite number "
                    f"of metres ≥ 0 ({rng:g} or more: the sensor sees nothing)"
                )
            d[PROX_NAMES.index(name)] = min(distance, rng)
        # what a calibrated e-puck sends for those distances (0 for nothing)
        raw = calibrated_from_distance(np.where(d < rng, d, np.inf))
        self._prox = Proximity(d, raw, rng)

    def set_ground(self, **values: float) -> None:
        """Set ground brightness 0 (black) .. 1 (white) by name; unnamed sensors see white."""
        v = np.ones(3)
        for name, value in values.items():
            if name not in GROUND_NAMES:
                raise ValueError(
                    f"unknown ground sensor {name!r}; names: {', '.join(GROUND_NAMES)}"
                )
            v[GROUND_NAMES.index(name)] = float(value)
        self._ground = Ground(v, v * 1023.0)

    # -- kinematics ------------------------------------------------------------------------
    def _velocity(self) -> tuple[float, float]:
        """The body's (forward m/s, turn rate rad/s) as its wheels, as built, drive it."""
        left, right = self.wheels
        radius_left, radius_right = self.actual.wheel_radii
        v_left, v_right = left * radius_left, right * radius_right
        return (v_left + v_right) / 2.0, (v_right - v_left) / self.actual.axle_length

    def _integrate(self, dt: float) -> None:
        left, right = self.wheels
        v, w = self._velocity()
        mid = self.theta + w * dt / 2.0
        self.x += v * dt * math.cos(mid)
        self.y += v * dt * math.sin(mid)
        self.theta = math.remainder(self.theta + w * dt, math.tau)
        self.encoders[0] += left * dt
        self.encoders[1] += right * dt

    # -- hooks -----------------------------------------------------------------------------
    def _read_sensors(self, sensors: frozenset[Sensor]) -> dict[Sensor, Any]:
        if self._replay is not None:
            frame = next(self._replay, None)
            if frame is not None:
                return {s: r for s, r in frame.items() if s in sensors}
        out: dict[Sensor, Any] = {}
        for s in sensors:
            if s is Sensor.PROXIMITY:
                out[s] = self._prox
            elif s is Sensor.GROUND:
                out[s] = self._ground
            elif s is Sensor.LIGHT:
                out[s] = Light(np.full(8, 3000.0))
            elif s is Sensor.ACCELERATION:
                out[s] = Acceleration(0.0, 0.0, GRAVITY)
            elif s is Sensor.GYRO:
                # ideal kinematics: the body turns exactly as the wheels say, at once
                out[s] = AngularVelocity(0.0, 0.0, self._velocity()[1])
            elif s is Sensor.ENCODERS:
                out[s] = WheelEncoders(*self.encoders)
            elif s is Sensor.WHEEL_SPEEDS:
                out[s] = WheelSpeeds(*self.wheels)
            elif s is Sensor.POSE:
                out[s] = Pose(self.x, self.y, self.theta, ground_truth=True)
        return out

    def _write_wheels(self, left: float, right: float) -> None:
        self.wheels = (left, right)
        self.commands.append((self.clock.time, left, right))

    def _read_camera(self) -> CameraImage:
        return self._image


def open_fake(
    scene: Scene | str,
    *,
    seed: int = 0,
    blackboard: Blackboard | None = None,
    command_timeout: float | None = None,
) -> Connection:
    """The ``fake`` backend: one :class:`FakeAdapter` per robot of ``scene``, at its start.

    Nothing is simulated but the robots' own wheels (ideal kinematics, no obstacles, no
    contacts); sensors read what a test sets. ``seed`` is accepted for the common factory
    signature and unused: the fake robot draws no random numbers. Select it like any other
    backend (``--backend fake``, ``open_backend("fake", ...)``, or the
    ``PUCKBOARD_BACKEND`` environment variable).
    """
    from ..profile import get_profile
    from ..scenario.scenefile import load_scene

    if isinstance(scene, str):
        scene = load_scene(scene)
    clock = FakeClock(scene.dt)
    board = blackboard if blackboard is not None else Blackboard(clock=lambda: clock.time)
    adapters: dict[str, RobotAdapter] = {
        spec.name: FakeAdapter(
            spec.name,
            profile=get_profile(spec.profile),
            blackboard=board,
            clock=clock,
            pose=(spec.x, spec.y, spec.theta),
            command_timeout=command_timeout,
            actual=spec.actual,
        )
        for spec in scene.robots
    }
    clock.start()
    return Connection(adapters=adapters, blackboard=board, stepper=clock)
