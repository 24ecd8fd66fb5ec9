"""One simulated e-puck that looks, byte for byte, like the real one.

:class:`EmulatedRobot` wraps a robot of the embedded simulator's
:class:`~puckboard.sim.world.World` and turns its state into the values the real robot
sends, with the same codecs and conversions :class:`~puckboard.backends.epuck.EPuckReal`
uses to read them (in the opposite direction):

* proximity: the world's calibrated IR values, rounded (the simulator already computes
  what the firmware sends: each sensor's response minus its start-up baseline, with the
  scene's noise, clamped at 0 as ``get_calibrated_prox`` does, so a client reading the
  field as unsigned never sees 65535, "touching"). ``K`` (:meth:`EmulatedRobot.calibrate_ir`)
  makes the simulated robot re-measure its baselines where it stands; and
  :class:`~puckboard.backends.epuck.EPuckReal` turns the values into distances through
  the same conversion the simulator uses
  (:func:`puckboard.ir_response.distance_from_calibrated`);
* ground: 0..1023 (0 black, 1023 white);
* step counters: int16 that wrap every 65536 steps;
* accelerometer: ≈768 counts per g, gravity on z;
* gyro: the simulated yaw rate at 131 counts per °/s (the chip's axes, as the robot
  sends them);
* camera: the world's camera renderer at the size asked (160×120 for Wi-Fi, 40×40 for
  sercom ``-'I'``), RGB565 on the wire.

Commands arrive in steps/s and are clamped at the e-puck2 firmware's 1100 steps/s.
Every method takes the robot's lock: protocol servers call it from their own threads
while the pacer steps the world.
"""

from __future__ import annotations

import math
import threading
import time

import numpy as np
import numpy.typing as npt

from ..blocks import ActuatorBlock, SensorBlock
from ..units import acceleration_to_raw, angular_velocity_to_raw, clamp_int16, wrap_int16

__all__ = ["MOTOR_SPEED_LIMIT", "EmulatedRobot"]

MOTOR_SPEED_LIMIT = 1100
"""steps/s; the e-puck2 firmware clamps every speed command to this (``motors.h``)."""

_AMBIENT = 3900  # IR ambient reading of a normally lit room (0 bright .. 4095 dark)


class EmulatedRobot:
    """Robot ``index`` of ``world``, spoken to in the real robot's units."""

    def __init__(self, world: object, index: int = 0, *, selector: int = 15) -> None:
        from ....sim.world import World

        if not isinstance(world, World):
            raise TypeError(f"EmulatedRobot needs a puckboard.sim.world.World, got {world!r}")
        self.world = world
        self.index = index
        self.name = world.robot_names[index]
        self.profile = world.profiles[index]
        self.selector = selector
        self.lock = threading.RLock()
        self.speeds = (0, 0)  # steps/s as last commanded
        self.leds = 0
        self.rgb: tuple[int, ...] = (0,) * 12
        self._step_offset = (0, 0)  # set by "set steps" commands
        self.commands = 0
        self.last_command = 0.0  # time.monotonic() of the last command
        self.calibrations = 0

    # -- actuators -------------------------------------------------------------------------
    def set_speeds(self, left: int, right: int) -> None:
        """Wheel speeds in steps/s, clamped like the firmware does."""
        lim = MOTOR_SPEED_LIMIT
        left = max(-lim, min(lim, int(left)))
        right = max(-lim, min(lim, int(right)))
        with self.lock:
            self.speeds = (left, right)
            p = self.profile
            self.world.set_wheel_speeds(self.index, p.steps_to_rad(left), p.steps_to_rad(right))

    def set_steps(self, left: int, right: int) -> None:
        """Set the step counters (sercom ``-'P'``, or the actuator block's bit 2)."""
        with self.lock:
            now = self._world_steps()
            self._step_offset = (int(left) - now[0], int(right) - now[1])

    def count_command(self) -> None:
        """Note a request from the client (the emulation's clock starts with the first; the
        idle timer restarts with each)."""
        with self.lock:
            self.commands += 1
            self.last_command = time.monotonic()

    def apply(self, block: ActuatorBlock) -> None:
        """Apply a "set all actuators" block (Wi-Fi 0x80 bytes 2..20, sercom 0x09)."""
        with self.lock:
            if block.settings & ActuatorBlock.CALIBRATE_IR:
                self.calibrate_ir()
            if block.settings & ActuatorBlock.SET_STEPS:
                self.set_steps(block.left, block.right)
            else:
                self.set_speeds(block.left, block.right)
            self.leds = block.leds
            self.rgb = block.rgb

    def stop(self) -> None:
        self.set_speeds(0, 0)

    def calibrate_ir(self) -> None:
        """Take the current IR readings as the new baselines, as the firmware does: an
        object in front of the robot during calibration blinds those sensors later
        (:meth:`~puckboard.sim.world.World.recalibrate_ir`)."""
        with self.lock:
            self.calibrations += 1
            self.world.recalibrate_ir(self.index)

    # -- sensors ---------------------------------------------------------------------------
    def _world_steps(self) -> tuple[int, int]:
        enc = self.world.encoders[self.index]
        rps = self.profile.rad_per_step
        return int(round(enc[0] / rps)), int(round(enc[1] / rps))

    def steps(self) -> tuple[int, int]:
        """The int16 step counters as the robot reports them (they wrap)."""
        with self.lock:
            s = self._world_steps()
            return (
                wrap_int16(s[0] + self._step_offset[0]),
                wrap_int16(s[1] + self._step_offset[1]),
            )

    def proximity(self) -> tuple[int, ...]:
        """8 calibrated IR values (int16), ps0..ps7."""
        with self.lock:
            return tuple(clamp_int16(v) for v in self.world.prox_raw[self.index].tolist())

    def ground(self) -> tuple[int, int, int]:
        with self.lock:
            g = np.clip(np.round(self.world.ground[self.index] * 1023.0), 0, 1023)
            return (int(g[0]), int(g[1]), int(g[2]))

    def accelerometer(self) -> tuple[int, int, int]:
        with self.lock:
            a = self.world.accelerations[self.index]
            raw = acceleration_to_raw((float(a[0]), float(a[1]), float(a[2])))
            return (clamp_int16(raw[0]), clamp_int16(raw[1]), clamp_int16(raw[2]))

    def gyro(self) -> tuple[int, int, int]:
        with self.lock:
            w = self.world.angular_velocities[self.index]
            return angular_velocity_to_raw((float(w[0]), float(w[1]), float(w[2])))

    def sensor_block(self) -> SensorBlock:
        """Every sensor as the e-puck2 encodes it (Wi-Fi 0x02 / sercom 0x08)."""
        with self.lock:
            acc = self.accelerometer()
            magnitude = math.sqrt(sum(float(v) * v for v in acc))
            dist = self.world.prox_distance[self.index]
            front = float(min(dist[0], dist[7]))
            tof = int(round(front * 1000)) if front < self.profile.prox_range else 2000
            return SensorBlock(
                acc=acc,
                acceleration=magnitude,
                orientation=0.0,
                inclination=0.0,
                gyro=self.gyro(),
                proximity=self.proximity(),
                ambient=(_AMBIENT,) * 8,
                tof_mm=tof,
                steps=self.steps(),
                selector=self.selector,
                ground=self.ground(),
                ground_ambient=(1000, 1000, 1000),
            )

    def camera(self, width: int, height: int) -> npt.NDArray[np.uint8]:
        """The camera image (H×W×3 uint8, upright) rendered at ``width``×``height``."""
        with self.lock:
            return self.world.render_camera(self.index, (width, height))
