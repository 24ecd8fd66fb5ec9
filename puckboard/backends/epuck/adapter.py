"""EPuckReal: the physical e-puck behind the same adapter contract as the simulators.

The source framework's EPuckReal was a proxy of the real robot next to EPuckVRep; here
it is one :class:`~puckboard.backends.base.RobotAdapter` whose link speaks either the
e-puck2 Wi-Fi protocol or advanced sercom. A controller does not change: records on the
blackboard have the same types and SI units as in simulation.

What differs from a simulator, on purpose:

* there is no simulation to step: :meth:`step` raises
  :class:`~puckboard.errors.NotSupportedError` and the control loop keeps a wall-clock
  period instead;
* ``pose`` is dead reckoning from the step counters (``ground_truth=False``), starting at
  the scene's start pose: a real robot has no ground truth;
* ``wheel_speeds`` are the commanded speeds (the robot does not measure them);
* ``gyro`` exists on the e-puck2 only (Wi-Fi, and sercom's all-sensors block); an
  e-puck1 link does not offer it, and enabling it there is a
  :class:`~puckboard.errors.NotSupportedError`;
* a lost link is final: every later call raises
  :class:`~puckboard.errors.ConnectionLostError` at once, and the adapter tries to stop
  the wheels on any error it sees. ``command_timeout`` (default 1 s) stops the wheels
  when the controller stops commanding them while sensing goes on.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from typing import Any, TypeVar

import numpy as np

from ...blackboard import Blackboard, Namespace
from ...errors import NotSupportedError
from ...profile import EPUCK2, RobotProfile
from ...records import (
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
from ..base import RobotAdapter
from .blocks import ActuatorBlock, SensorBlock
from .link import Link
from .units import (
    StepCounterUnwrapper,
    acceleration_from_raw,
    angular_velocity_from_raw,
    clamp_int16,
    distance_from_calibrated,
    ground_value_from_raw,
    rad_s_to_steps_s,
)

__all__ = ["EPuckReal"]

log = logging.getLogger(__name__)

T = TypeVar("T")


class EPuckReal(RobotAdapter):
    """A physical e-puck reached through ``link`` (a Wi-Fi or sercom link).

    Use :func:`~puckboard.backends.epuck.open_wifi` / :func:`open_sercom` rather than
    building one by hand; they also make the blackboard and the connection.
    ``image_rotation`` turns camera images by that many quarter turns counter-clockwise,
    for robots whose camera is mounted sideways.
    """

    available_sensors = frozenset(
        {
            Sensor.PROXIMITY,
            Sensor.GROUND,
            Sensor.LIGHT,
            Sensor.ACCELERATION,
            Sensor.GYRO,
            Sensor.ENCODERS,
            Sensor.WHEEL_SPEEDS,
            Sensor.POSE,
            Sensor.CAMERA,
        }
    )
    backend_name = "real"

    def __init__(
        self,
        link: Link,
        name: str = "epuck",
        *,
        profile: RobotProfile = EPUCK2,
        blackboard: Blackboard | Namespace | None = None,
        command_timeout: float | None = 1.0,
        start_pose: tuple[float, float, float] = (0.0, 0.0, 0.0),
        image_rotation: int = 0,
    ) -> None:
        self.link = link
        self.image_rotation = int(image_rotation) % 4
        self.backend_name = link.backend_name
        # the gyro is the e-puck2's: a link says whether its robot sends one
        self._has_gyro = bool(getattr(link, "has_gyro", False))
        if not self._has_gyro:
            self.available_sensors = type(self).available_sensors - {Sensor.GYRO}
        super().__init__(
            name, profile=profile, blackboard=blackboard, command_timeout=command_timeout
        )
        self._actuators = ActuatorBlock()
        self._commanded = (0.0, 0.0)
        self._unwrap = StepCounterUnwrapper()
        self._last_steps: tuple[int, int] | None = None
        self._pose = [float(start_pose[0]), float(start_pose[1]), float(start_pose[2])]
        self.last_block: SensorBlock | None = None

    # -- hooks -------------------------------------------------------------------------
    def _read_sensors(self, sensors: frozenset[Sensor]) -> dict[Sensor, Any]:
        reply = self._guarded(
            lambda: self.link.exchange(self._actuators, sensors=True, image=False)
        )
        assert reply.sensors is not None
        return self._records(reply.sensors, sensors)

    def _write_wheels(self, left: float, right: float) -> None:
        block = ActuatorBlock(
            left=clamp_int16(rad_s_to_steps_s(left, self.profile)),
            right=clamp_int16(rad_s_to_steps_s(right, self.profile)),
            leds=self._actuators.leds,
            rgb=self._actuators.rgb,
        )
        self._actuators = block
        self._commanded = (left, right)
        if self.link_broken and (self._closed or (left == 0.0 and right == 0.0)):
            return  # nothing to send to; let close() finish instead of raising twice
        self._guarded(lambda: self.link.exchange(block, sensors=False, image=False))

    def _read_camera(self) -> CameraImage:
        reply = self._guarded(
            lambda: self.link.exchange(self._actuators, sensors=False, image=True)
        )
        assert reply.image is not None
        image = reply.image
        if self.image_rotation:
            image = np.ascontiguousarray(np.rot90(image, self.image_rotation))
        return CameraImage(image)

    def _close(self) -> None:
        self.link.close()

    # -- extras ------------------------------------------------------------------------
    def set_leds(
        self,
        mask: int = 0,
        rgb: tuple[int, ...] = (0,) * 12,
    ) -> None:
        """Set the LEDs, sent with the next exchange.

        ``mask`` bits: 0 LED1 (front), 1 LED3 (right), 2 LED5 (back), 3 LED7 (left),
        4 body, 5 front LED. ``rgb``: LED2, LED4, LED6, LED8 as r, g, b each 0..100
        (e-puck2 only).
        """
        if any(not 0 <= c <= 100 for c in rgb):
            raise ValueError(f"RGB LED values go from 0 to 100, got {rgb}")
        a = self._actuators
        with self.io_lock:
            self._actuators = ActuatorBlock(left=a.left, right=a.right, leds=mask, rgb=tuple(rgb))

    def calibrate_ir(self) -> None:
        """Ask the e-puck2 to re-measure its IR baselines (nothing may be within ~10 cm).

        The robot also calibrates when it starts, so switch it on in free space. e-puck1
        firmware offers this only in ASCII mode (``K``): use GCtronic's tools there.
        """
        if getattr(self.link, "model", "e-puck2") != "e-puck2":
            raise NotSupportedError(
                "IR calibration over binary sercom needs an e-puck2; on an e-puck1 restart the "
                "robot with nothing in front of it (it calibrates at start-up)"
            )
        a = self._actuators
        block = ActuatorBlock(
            left=a.left, right=a.right, leds=a.leds, rgb=a.rgb, settings=ActuatorBlock.CALIBRATE_IR
        )
        with self.io_lock:
            self._ensure_open()
            self._guarded(lambda: self.link.exchange(block, sensors=False, image=False))

    @property
    def link_broken(self) -> bool:
        return bool(getattr(self.link, "broken", False))

    @property
    def wheels_stopped(self) -> bool:
        """Over a broken link no stop reached the robot, whatever was last commanded."""
        return super().wheels_stopped and not self.link_broken

    # -- internals ---------------------------------------------------------------------
    def _guarded(self, fn: Callable[[], T]) -> T:
        """Run one exchange; on failure try (once, briefly) to stop the wheels, re-raise."""
        try:
            return fn()
        except Exception:
            self._emergency_stop()
            raise

    def _emergency_stop(self) -> None:
        self._actuators = ActuatorBlock(leds=self._actuators.leds, rgb=self._actuators.rgb)
        self._commanded = (0.0, 0.0)
        self._wheels_moving = False
        if self.link_broken:
            return
        try:
            self.link.exchange(self._actuators, sensors=False, image=False)
        except Exception as exc:  # the link is in trouble already; the caller gets the first error
            log.debug("robot %r: stopping the wheels after an error failed too: %s", self.name, exc)

    def _records(self, block: SensorBlock, wanted: frozenset[Sensor]) -> dict[Sensor, Any]:
        self.last_block = block
        p = self.profile
        out: dict[Sensor, Any] = {}
        # a firmware that does not clamp may send negatives: below the baseline is nothing
        raw = np.clip(np.asarray(block.proximity, dtype=np.float64), 0.0, None)
        out[Sensor.PROXIMITY] = Proximity(distance_from_calibrated(raw, p), raw, p.prox_range)
        graw = np.asarray(block.ground, dtype=np.float64)
        out[Sensor.GROUND] = Ground(ground_value_from_raw(graw), graw)
        out[Sensor.LIGHT] = Light(np.asarray(block.ambient, dtype=np.float64))
        counts, offset = self.link.acc_scale
        ax, ay, az = acceleration_from_raw(block.acc, counts, offset)
        out[Sensor.ACCELERATION] = Acceleration(ax, ay, az)
        if self._has_gyro:
            out[Sensor.GYRO] = AngularVelocity(*angular_velocity_from_raw(block.gyro))
        steps = self._unwrap.update(*block.steps)
        out[Sensor.ENCODERS] = WheelEncoders(p.steps_to_rad(steps[0]), p.steps_to_rad(steps[1]))
        out[Sensor.WHEEL_SPEEDS] = WheelSpeeds(*self._commanded)
        self._integrate_odometry(steps)
        out[Sensor.POSE] = Pose(self._pose[0], self._pose[1], self._pose[2], ground_truth=False)
        return {s: r for s, r in out.items() if s in wanted}

    def _integrate_odometry(self, steps: tuple[int, int]) -> None:
        if self._last_steps is not None:
            p = self.profile
            dl = p.steps_to_rad(steps[0] - self._last_steps[0]) * p.wheel_radius
            dr = p.steps_to_rad(steps[1] - self._last_steps[1]) * p.wheel_radius
            ds = (dl + dr) / 2.0
            dtheta = (dr - dl) / p.axle_length
            mid = self._pose[2] + dtheta / 2.0
            self._pose[0] += ds * math.cos(mid)
            self._pose[1] += ds * math.sin(mid)
            self._pose[2] = math.atan2(
                math.sin(self._pose[2] + dtheta), math.cos(self._pose[2] + dtheta)
            )
        self._last_steps = steps
