"""The adapter contract: one robot, whatever is behind it.

This is the source framework's DifferentialWheels → EPuck abstraction. A concrete adapter
(embedded simulator, CoppeliaSim, real e-puck, fake) implements four small hooks; this
base class supplies everything users call, and supplies it the same way for every
backend:

* ``sense_all()`` reads every enabled sensor in one round trip (the source framework's
  senseAllTogether) and writes the records to the robot's blackboard namespace in one
  atomic write, so a snapshot never mixes two sensing cycles;
* ``refresh(sensor)`` reads one sensor;
* ``command_wheels(command)``: a controller's :class:`~puckboard.records.WheelCommand`
  (rad/s), clamped once, here, to the profile's limit with one warning per robot
  (``set_wheel_speeds(left, right)`` is the same for two numbers);
* ``camera_image()``;
* for simulators, synchronous stepping through a shared :class:`Stepper`;
* a background sensing thread and camera thread with their own periods, and observers
  that learn which sensors changed or receive each new image
  (:class:`~puckboard.backends.sensing_threads.SensingThreads`);
* ``close()``, which zeroes the wheels first.

Every call into the transport goes through one lock per adapter. The source framework
crashed when a sensing thread's remote call overlapped the controller's wheel command
(its §5.1.4); here the hooks are only ever called with that lock held, so the overlap is
impossible by construction, not by discipline.
"""

from __future__ import annotations

import abc
import logging
import threading
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, Protocol, runtime_checkable

from ..blackboard import Blackboard, InstanceOf, Namespace
from ..errors import AdapterClosedError, NotSupportedError
from ..profile import EPUCK2, RobotProfile
from ..records import RECORD_TYPES, CameraImage, Sensor, WheelCommand
from .sensing_threads import SensingThreads

__all__ = ["Connection", "RobotAdapter", "Stepper", "declare_robot_keys"]

log = logging.getLogger(__name__)


@runtime_checkable
class Stepper(Protocol):
    """A synchronously stepped simulation shared by all robots in it.

    One stepper per world: with two robots in one simulation, the control loop steps the
    world once per cycle, not once per robot. A protocol rather than a base class, so the
    embedded engine satisfies it without importing anything of the adapters.
    """

    @property
    def dt(self) -> float:
        """Length of one simulation step (s)."""
        ...

    @property
    def time(self) -> float:
        """Current simulation time (s)."""
        ...

    def start(self) -> None:
        """Start (or resume) the simulation in stepping mode."""
        ...

    def step(self, n: int = 1) -> None:
        """Advance ``n`` steps and return when they are done."""
        ...

    def stop(self) -> None:
        """Stop the simulation."""
        ...


@dataclass
class Connection:
    """What a backend factory (``open_backend(name, scene, ...)``) returns.

    ``adapters`` maps robot names to their adapters, all writing into ``blackboard``;
    ``stepper`` is the shared simulation for synchronous backends (``None`` on a real
    robot); ``world`` is the embedded simulator's world when there is one (ground truth
    for judging and drawing), else ``None``.
    """

    adapters: dict[str, RobotAdapter]
    blackboard: Blackboard
    stepper: Stepper | None = None
    world: Any = None
    extra_close: list[Callable[[], None]] = field(default_factory=list)

    def close(self) -> None:
        """Close every adapter (wheels zeroed first), then the backend's own resources."""
        for adapter in self.adapters.values():
            try:
                adapter.close()
            except Exception as exc:
                log.warning("closing robot %r failed: %s", adapter.name, exc)
        for fn in self.extra_close:
            try:
                fn()
            except Exception as exc:
                log.warning("closing backend resource failed: %s", exc)

    def __enter__(self) -> Connection:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def declare_robot_keys(ns: Namespace, max_age: float | None = None) -> None:
    """Declare the schema of every sensor key (and the command keys) in ``ns``.

    A value of the wrong type (a bare array instead of a :class:`~puckboard.records.Proximity`
    record, say) is then refused with an error naming the key. Sensor records older
    than ``max_age`` (s) count as stale, the camera's excepted. An adapter declares its
    own namespace (:meth:`RobotAdapter.set_stale_after` changes the age); call this only
    for a namespace no adapter writes, a test's or a benchmark's.
    """
    for sensor, cls in RECORD_TYPES.items():
        age = None if sensor is Sensor.CAMERA else max_age  # images come at their own pace
        ns.declare(sensor.key, schema=InstanceOf(cls), max_age=age)
    ns.declare("command/wheels", schema=InstanceOf(WheelCommand))
    ns.declare("command/layer", schema=InstanceOf(str))


class RobotAdapter(SensingThreads, abc.ABC):
    """Base class of every robot backend; see the module docstring.

    Subclasses implement :meth:`_read_sensors`, :meth:`_write_wheels`,
    :meth:`_read_camera` and :meth:`_close`, and say which sensors they have in
    :attr:`available_sensors`. The hooks are always called with :attr:`io_lock` held.
    """

    #: Sensors this backend can deliver (subclasses narrow it).
    available_sensors: frozenset[Sensor] = frozenset(Sensor)
    #: Sensors this backend has but reads only once asked (:meth:`enable`). The camera
    #: is always among them (an image is its own, slow round trip); a backend adds a
    #: sensor that would cost every cycle something few controllers need. Everything
    #: else available is enabled when the adapter opens.
    opt_in_sensors: frozenset[Sensor] = frozenset({Sensor.CAMERA})
    #: The backend's name as used by ``--backend``.
    backend_name: str = "abstract"

    def __init__(
        self,
        name: str = "epuck",
        *,
        profile: RobotProfile = EPUCK2,
        blackboard: Blackboard | Namespace | None = None,
        stepper: Stepper | None = None,
        command_timeout: float | None = None,
    ) -> None:
        self.name = name
        self.profile = profile
        self.stepper = stepper
        self.command_timeout = command_timeout
        self.io_lock = threading.RLock()
        self._enabled: set[Sensor] = set(self.available_sensors) - self.opt_in_sensors
        self._sense_all_reads = frozenset(self._enabled - {Sensor.CAMERA})
        self._stale_after: float | None = None
        self._closed = False
        self._clamp_warned = False
        self._last_command_time: float | None = None
        self._wheels_moving = False
        SensingThreads.__init__(self)
        self.ns: Namespace = self._make_namespace(blackboard)

    # -- blackboard ------------------------------------------------------------------------
    def _make_namespace(self, board: Blackboard | Namespace | None) -> Namespace:
        if isinstance(board, Namespace):
            ns = board
        else:
            if board is None:
                stepper = self.stepper
                clock = (lambda: stepper.time) if stepper is not None else time.monotonic
                board = Blackboard(clock=clock)
            ns = board.namespace(self.name)
        declare_robot_keys(ns, max_age=self._stale_after)
        # each sensor's absolute key, spelt once: a record per sensor is written every cycle
        self._keys = {sensor: ns.prefix + sensor.key for sensor in Sensor}
        return ns

    def set_stale_after(self, seconds: float | None) -> None:
        """Let this robot's sensor records count as stale once older than ``seconds``
        (None: never). A control loop sets it from its period; the adapter owns its
        namespace's key declarations, so they are made in this one place."""
        self._stale_after = seconds
        declare_robot_keys(self.ns, max_age=seconds)

    def attach(self, board: Blackboard | Namespace) -> Namespace:
        """Write into ``board`` (under this robot's name, or into the given namespace)."""
        self.ns = self._make_namespace(board)
        return self.ns

    @property
    def blackboard(self) -> Blackboard:
        return self.ns.board

    def now(self) -> float:
        """Time stamp for new readings: simulation time, else the blackboard's clock."""
        return self.stepper.time if self.stepper is not None else self.ns.board.clock()

    # -- sensors ---------------------------------------------------------------------------
    def enable(self, *sensors: Sensor | str) -> None:
        """Enable sensors for ``sense_all`` and the sensing thread; the ones in
        :attr:`opt_in_sensors` (the camera, and on some backends e.g. the gyro) start off."""
        for s in map(_as_sensor, sensors):
            if s not in self.available_sensors:
                raise NotSupportedError(
                    f"{self.backend_name} robot {self.name!r} has no {s.value} sensor; "
                    f"available: {', '.join(sorted(x.value for x in self.available_sensors))}"
                )
            self._enabled.add(s)
        self._sense_all_reads = frozenset(self._enabled - {Sensor.CAMERA})

    def disable(self, *sensors: Sensor | str) -> None:
        for s in map(_as_sensor, sensors):
            self._enabled.discard(s)
        self._sense_all_reads = frozenset(self._enabled - {Sensor.CAMERA})

    @property
    def enabled_sensors(self) -> frozenset[Sensor]:
        return frozenset(self._enabled)

    def sense_all(self) -> dict[Sensor, Any]:
        """Read every enabled sensor (camera excepted) in one round trip; write the records.

        Returns the records by sensor. Sensor observers are told which sensors changed.
        """
        with self.io_lock:
            self._ensure_open()
            records = self._read_sensors(self._sense_all_reads)
            stamp = self.now()
        self._publish(records, stamp)
        self._check_watchdog()
        return records

    def refresh(self, sensor: Sensor | str) -> Any:
        """Read one sensor now (a separate round trip) and write its record."""
        s = _as_sensor(sensor)
        if s is Sensor.CAMERA:
            return self.camera_image()
        if s not in self.available_sensors:
            raise NotSupportedError(f"{self.backend_name} robot {self.name!r} has no {s.value}")
        with self.io_lock:
            self._ensure_open()
            records = self._read_sensors(frozenset({s}))
            stamp = self.now()
        self._publish(records, stamp)
        return records[s]

    def camera_image(self) -> CameraImage:
        """Grab an upright camera image, write it to the blackboard and tell camera observers."""
        if Sensor.CAMERA not in self.available_sensors:
            raise NotSupportedError(f"{self.backend_name} robot {self.name!r} has no camera")
        with self.io_lock:
            self._ensure_open()
            image = self._read_camera()
            stamp = self.now()
        self.ns.put(Sensor.CAMERA.key, image, stamp=stamp, writer=self.name)
        self._tell_camera_observers(image)
        return image

    def _publish(self, records: Mapping[Sensor, Any], stamp: float) -> None:
        if not records:
            return
        # One dict keyed by the absolute keys, written straight to the board (what
        # ``Namespace.write_many`` does after re-keying a second dict).
        keys = self._keys
        self.ns.board.write_many(
            {keys[s]: r for s, r in records.items()}, stamp=stamp, writer=self.name
        )
        if self._sensor_observers:  # no set to build on the usual, unobserved cycle
            self._tell_sensor_observers(frozenset(records))

    # -- actuators -------------------------------------------------------------------------
    def command_wheels(self, command: WheelCommand) -> WheelCommand:
        """Send a wheel command (rad/s), as a controller's tick returns it. Returns the
        command actually sent.

        Beyond the profile's limit the speed is clamped, here and only here, with a
        warning logged once per robot: the adapter is the one place that knows the
        robot's profile and name whatever is behind it (a real robot, CoppeliaSim, the
        embedded engine), so every backend clamps the same way and the transport below
        (:meth:`_write_wheels`) receives numbers already within the limit.
        """
        cmd = self._clamp(command)
        with self.io_lock:
            self._ensure_open()
            self._write_wheels(cmd.left, cmd.right)
        self._last_command_time = time.monotonic()
        self._wheels_moving = cmd.left != 0.0 or cmd.right != 0.0
        return cmd

    def set_wheel_speeds(self, left: float, right: float) -> WheelCommand:
        """Command the wheels (rad/s): :meth:`command_wheels` for two numbers."""
        return self.command_wheels(WheelCommand(float(left), float(right)))

    def stop_wheels(self) -> None:
        """Command both wheels to zero."""
        self.command_wheels(WheelCommand.stop())

    def _clamp(self, cmd: WheelCommand) -> WheelCommand:
        """``cmd`` within the profile's limit, as floats (a layer may have built it of ints)."""
        limit = self.profile.max_wheel_speed
        if abs(cmd.left) <= limit and abs(cmd.right) <= limit:
            if type(cmd.left) is float and type(cmd.right) is float:
                return cmd
            return WheelCommand(float(cmd.left), float(cmd.right))
        if not self._clamp_warned:
            log.warning(
                "robot %r: wheel command (%.3f, %.3f) rad/s exceeds the %s limit of %.3f rad/s; "
                "clamping (this warning is shown once per robot)",
                self.name, cmd.left, cmd.right, self.profile.name, limit,
            )  # fmt: skip
            self._clamp_warned = True
        left, right = float(cmd.left), float(cmd.right)
        return WheelCommand(max(-limit, min(limit, left)), max(-limit, min(limit, right)))

    def _check_watchdog(self) -> None:
        """Stop the wheels when the last command is older than ``command_timeout`` (wall s)."""
        if self.command_timeout is None or not self._wheels_moving or self._closed:
            return
        last = self._last_command_time
        if last is not None and time.monotonic() - last > self.command_timeout:
            log.warning(
                "robot %r: no wheel command for %.2f s; stopping the wheels",
                self.name,
                self.command_timeout,
            )
            self.stop_wheels()

    # -- stepping --------------------------------------------------------------------------
    def _require_stepper(self) -> Stepper:
        if self.stepper is None:
            raise NotSupportedError(
                f"{self.backend_name} robot {self.name!r} runs in real time and cannot be "
                "stepped; use a wall-clock ControlLoop (period=...) instead"
            )
        return self.stepper

    def start_simulation(self) -> None:
        self._require_stepper().start()

    def step(self, n: int = 1) -> None:
        """Advance the shared simulation ``n`` steps (every robot in it moves)."""
        self._require_stepper().step(n)

    def stop_simulation(self) -> None:
        self._require_stepper().stop()

    # -- lifecycle -------------------------------------------------------------------------
    @property
    def closed(self) -> bool:
        return self._closed

    @property
    def wheels_stopped(self) -> bool:
        """Whether the last wheel command known to have reached the robot was a stop (or
        none was sent): after a lost connection, ``False`` means it may still be driving."""
        return not self._wheels_moving

    def close(self) -> None:
        """Stop the threads, zero the wheels (best effort), release the transport. Idempotent."""
        if self._closed:
            return
        self.stop_threads()
        try:
            with self.io_lock:
                self._write_wheels(0.0, 0.0)
            self._wheels_moving = False
        except Exception as exc:  # the transport may already be gone
            log.warning("robot %r: could not zero the wheels on close: %s", self.name, exc)
        finally:
            self._closed = True
            with self.io_lock:
                self._close()

    def __enter__(self) -> RobotAdapter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _ensure_open(self) -> None:
        if self._closed:
            raise AdapterClosedError(f"robot {self.name!r} ({self.backend_name}) is closed")

    def __repr__(self) -> str:
        state = "closed" if self._closed else "open"
        return f"<{type(self).__name__} {self.name!r} {self.profile.name} {state}>"

    # -- hooks for subclasses (called with io_lock held) -----------------------------------
    @abc.abstractmethod
    def _read_sensors(self, sensors: frozenset[Sensor]) -> dict[Sensor, Any]:
        """Read ``sensors`` in as few round trips as possible; return SI records."""

    @abc.abstractmethod
    def _write_wheels(self, left: float, right: float) -> None:
        """Send wheel speeds (rad/s, already clamped)."""

    def _read_camera(self) -> CameraImage:
        raise NotSupportedError(f"{self.backend_name} has no camera")

    def _close(self) -> None:
        """Release the transport."""


def _as_sensor(s: Sensor | str) -> Sensor:
    if isinstance(s, Sensor):
        return s
    try:
        return Sensor(s)
    except ValueError:
        known = ", ".join(x.value for x in Sensor)
        raise ValueError(f"unknown sensor {s!r}; known sensors: {known}") from None
