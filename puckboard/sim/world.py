"""The embedded simulator's world: the robots' state and the step that moves them, one clock.

A :class:`World` is built from a :class:`~puckboard.scenario.scene.Scene` and stepped
synchronously (it satisfies the stepping protocol every embedded robot shares,
:class:`~puckboard.backends.base.Stepper`). Each :meth:`World.step`:

0. with a control latency (the scene's ``control.latency``, whole steps), hands the
   wheels the commands that arrive at this step, each given that many steps before;
1. lets the ground act on each robot's wheel command: times ``1 + σ·N(0, 1)``
   wheel-speed noise, clamped to the profile's limit;
2. moves every robot along its exact arc (:mod:`.kinematics`), each wheel rolling its
   own true radius, in sub-steps short enough that nothing can tunnel, resolving
   contacts after each (:mod:`.contacts`);
3. updates the encoders (the commanded rotation), the accelerometers (the velocity
   change), the gyros (the heading change) and the collision counts;
4. senses: every IR and ground sensor of every robot in a few vectorised calls
   (:mod:`.sensing`).

Each robot is simulated as it is built (:attr:`World.actual`: the scene's
``RobotSpec.actual`` when a plausible robot was drawn, else its profile), while
:attr:`World.profiles` keeps what the robot believes it is (the scene's profile, with
its overrides): the adapters, and with them odometry and unit conversions, use that.

The results live in N×k arrays (``poses``, ``prox_distance``, ``ground`` ...), written in
place, so a read-only view of a robot's rows (:meth:`World.robot_arrays`) stays live. The
engine builds no records and knows no adapter: the embedded backend turns a robot's rows
into records. The camera is rendered on demand (:meth:`World.render_camera`) and is
noise-free, so rendering never changes a run.

Speed: a usual scene has a few robots, for which a numpy call costs more than the
arithmetic it would vectorise, so the step's per-robot loops run on plain Python floats.
The state those loops carry from step to step (poses, velocities, who is touching
something, the wheel commands) is kept as Python lists, and the poses are copied into
their array once per step; everything else is stored once, in the arrays.

Randomness: one ``np.random.Generator(PCG64(seed))`` per world draws the start-pose
jitter at construction and then, each step, one block of :data:`NORMALS_PER_ROBOT`
normals per robot (the wheels, the IR sensors, the ground sensors), always the same
number whatever is read, so the same seed gives the same arrays with or without a
viewer. Gyro noise, when the scene sets some, is one more block of N normals per step
after it.

See docs/simulator.md for every model's source and the choices made.
"""

from __future__ import annotations

import logging
import math
import threading
import time
from typing import NamedTuple

import numpy as np
import numpy.typing as npt

from ..profile import RobotProfile, get_profile
from ..records import GRAVITY
from ..scenario.scene import Scene
from .camera import RobotCameras
from .contacts import Statics
from .floor import Floor
from .kinematics import arc
from .link_cycles import LinkCycleState
from .sensing import Sensing
from .surfaces import stack_surfaces

__all__ = ["IR_RAYS", "NORMALS_PER_ROBOT", "RobotArrays", "World"]

log = logging.getLogger(__name__)

FloatArray = npt.NDArray[np.float64]

#: Rays cast per IR sensor, spread evenly across the sensor's aperture.
IR_RAYS = 5
#: Largest distance (as a fraction of the body radius) a robot may move in one physics
#: sub-step; longer steps are split so contacts are never skipped.
MAX_SUBSTEP_FRACTION = 0.25
#: Standard normals drawn per robot each step of a noisy world, in blocks of N robots:
#: 2 for the wheels, then 8 for the IR sensors, then 3 for the ground sensors.
NORMALS_PER_ROBOT = 13


class RobotArrays(NamedTuple):
    """One robot's rows of the world's arrays, SI units, as read-only views.

    The views are live: the world writes its arrays in place every step. Hold
    :attr:`World.lock` while reading several of them, so that a step in another thread
    cannot fall between two reads.
    """

    pose: FloatArray  #: x (m), y (m), theta (rad in (-π, π])
    wheel_speeds: FloatArray  #: left, right (rad/s)
    encoders: FloatArray  #: left, right accumulated rotation (rad)
    prox_distance: FloatArray  #: ps0..ps7 (m; exactly the range where nothing is seen)
    prox_raw: FloatArray  #: ps0..ps7 calibrated, as an e-puck sends them (0 nothing .. 4095)
    ground: FloatArray  #: left, centre, right brightness (0..1)
    ground_raw: FloatArray  #: left, centre, right on the e-puck's scale (0..1023)
    acceleration: FloatArray  #: robot frame (m/s², gravity on z)
    angular_velocity: FloatArray  #: robot frame (rad/s, the yaw rate on z)


class World:
    """A simulated scene; see the module docstring.

    ``ir_rays`` rays per IR sensor (odd, so one looks straight ahead) and
    ``ground_footprint`` (m, half-width of a ground sensor's spot, 0 for a point
    sample; replaces every profile's own when given) tune the sensor models; the
    defaults are documented in docs/simulator.md.
    """

    def __init__(
        self,
        scene: Scene,
        *,
        seed: int = 0,
        ir_rays: int = IR_RAYS,
        ground_footprint: float | None = None,
    ) -> None:
        if not scene.robots:
            raise ValueError(f"scene {scene.name!r} has no robots; add at least one [[robots]]")
        if not scene.dt > 0:
            raise ValueError(f"scene dt must be positive seconds, got {scene.dt}")
        self.scene = scene
        self.seed = seed
        self.rng = np.random.Generator(np.random.PCG64(seed))
        # a camera or sensing thread may read while the control loop steps
        self._lock = threading.RLock()
        self._dt = float(scene.dt)
        self._time = 0.0
        self.step_count = 0
        #: wall time (s) spent in the sensor models during steps, for benchmarks
        self.sensor_seconds = 0.0
        self.running = False
        self.robot_names: tuple[str, ...] = tuple(r.name for r in scene.robots)
        if len(set(self.robot_names)) != len(self.robot_names):
            raise ValueError(f"robot names must be unique, got {list(self.robot_names)}")
        #: what each robot believes it is: the scene's profile (with its overrides)
        self.profiles: tuple[RobotProfile, ...] = tuple(
            get_profile(r.profile) for r in scene.robots
        )
        #: what each robot is, as built: what the world simulates
        self.actual: tuple[RobotProfile, ...] = tuple(
            r.actual if r.actual is not None else p for r, p in zip(scene.robots, self.profiles)
        )
        self.n = len(scene.robots)
        # the numbers the step's loops read, as plain floats
        self._wheel_radii = tuple(
            (float(p.wheel_radii[0]), float(p.wheel_radii[1])) for p in self.actual
        )
        self._axle = tuple(float(p.axle_length) for p in self.actual)
        self._max_wheel = tuple(float(p.max_wheel_speed) for p in self.actual)
        self._body_radius = tuple(float(p.body_radius) for p in self.actual)
        noise = scene.noise
        self._noise_wheel = float(noise.wheel_speed)
        self._noisy = self._noise_wheel > 0 or noise.proximity > 0 or noise.ground > 0
        self._noise_gyro = float(noise.gyro)
        self._gyro_bias = float(noise.gyro_bias)
        # the loop's latency (scene.control), in steps: a command given now turns the
        # wheels this many steps later (0: at once, the thesis's synchronous loop)
        self._delay = scene.control.steps(self._dt)[1]
        # a link that varies cycle by cycle (a latency drawn per command, repeated
        # readings) runs its own queue instead of the fixed ring (sim/link_cycles.py)
        self._cycles = (
            LinkCycleState(scene.control, len(scene.robots), seed=seed, dt=self._dt)
            if scene.control.varies
            else None
        )
        if self._cycles is not None:
            self._delay = 0

        self._init_state()

        # -- static geometry and the sensors -----------------------------------------------
        self.floor = (
            Floor(scene) if ground_footprint is None else Floor(scene, footprint=ground_footprint)
        )
        self.statics = Statics(scene.obstacles, scene.arena)
        surfaces = stack_surfaces(scene, np.array(self._body_radius))
        self.sensing = Sensing(
            self.actual,
            self.floor,
            surfaces,
            rays=ir_rays,
            proximity_noise=float(noise.proximity),
            ground_noise=float(noise.ground),
            ground_footprint=ground_footprint,
        )
        #: each robot's ground-sensor footprint (m), as the world reads its floor
        self.ground_footprints: tuple[float, ...] = tuple(
            float(p.ground_footprint if ground_footprint is None else ground_footprint)
            for p in self.actual
        )
        self._cameras = RobotCameras(self.floor, surfaces, self.actual, scene.camera_size)
        # the first contact check and sensor pass describe the start pose (time 0)
        self._resolve_start_contacts()
        self.sensing.sense(self._pose_list, None, None)
        self._read_only_views()

    # -- construction helpers ----------------------------------------------------------------
    def _init_state(self) -> None:
        """The robots' moving state: poses (with start jitter), wheels, encoders, IMU."""
        scene, n, noise = self.scene, self.n, self.scene.noise
        self._poses = np.array([[r.x, r.y, r.theta] for r in scene.robots], dtype=float)
        if noise.start_jitter > 0:
            self._poses += self.rng.normal(0.0, noise.start_jitter, size=(n, 3))
        self._poses[:, 2] = np.remainder(self._poses[:, 2] + math.pi, math.tau) - math.pi
        self._wheels = np.zeros((n, 2))
        self._encoders = np.zeros((n, 2))
        self._accel = np.zeros((n, 3))
        self._accel[:, 2] = GRAVITY
        # gyro: a planar world turns only about z, so x and y stay zero
        self._gyro = np.zeros((n, 3))
        self._gyro_z = self._gyro[:, 2]
        self._collisions = np.zeros(n, dtype=np.int64)
        self._contacts = np.zeros(n, dtype=bool)
        self._max_substep_move = MAX_SUBSTEP_FRACTION * min(self._body_radius)
        # the state the step's loops carry, as Python lists (see the module docstring):
        # the wheel commands (left, right), set once per robot per cycle and read once
        # per step; the poses the loops move and the contacts resolve in place; the last
        # step's velocities (for the accelerometer); who touched something last step
        self._command: list[tuple[float, float]] = [(0.0, 0.0)] * n
        self._pose_list: list[list[float]] = self._poses.tolist()
        self._velocity: list[tuple[float, float]] = [(0.0, 0.0)] * n
        self._touching: list[bool] = [False] * n
        # commands on their way to the wheels, by the step at which they arrive: slot
        # ``step % (delay + 1)`` holds each robot's command due at that step, or None
        # (a fixed ring, written in place: no allocation per step)
        self._due: list[list[tuple[float, float] | None]] = [
            [None] * n for _ in range(self._delay + 1 if self._delay else 0)
        ]

    def _read_only_views(self) -> None:
        def ro(a: np.ndarray) -> np.ndarray:
            v = a.view()
            v.flags.writeable = False
            return v

        s = self.sensing
        self._views = {
            "poses": ro(self._poses),
            "wheel_speeds": ro(self._wheels),
            "encoders": ro(self._encoders),
            "prox_distance": ro(s.prox_distance),
            "prox_raw": ro(s.prox_raw),
            "ground": ro(s.ground),
            "ground_raw": ro(s.ground_raw),
            "collisions": ro(self._collisions),
            "contacts_now": ro(self._contacts),
            "accelerations": ro(self._accel),
            "angular_velocities": ro(self._gyro),
        }
        v = self._views
        self._robot_arrays = [
            RobotArrays(
                pose=v["poses"][i],
                wheel_speeds=v["wheel_speeds"][i],
                encoders=v["encoders"][i],
                prox_distance=v["prox_distance"][i],
                prox_raw=v["prox_raw"][i],
                ground=v["ground"][i],
                ground_raw=v["ground_raw"][i],
                acceleration=v["accelerations"][i],
                angular_velocity=v["angular_velocities"][i],
            )
            for i in range(self.n)
        ]

    def _resolve_start_contacts(self) -> None:
        """Move robots that start overlapping something clear of it, and say which robot
        overlapped what and how far it was moved: a silent move would hide a scene typo."""
        pos = self._pose_list
        overlaps = [self._start_overlaps(i) for i in range(self.n)]
        contact = self.statics.resolve(pos, self._body_radius)
        for i, (x, y, _) in enumerate(self._poses.tolist()):
            moved = math.hypot(pos[i][0] - x, pos[i][1] - y)
            if moved > 1e-9:
                log.warning(
                    "scene %r: robot %r starts overlapping %s; moved it %.1f cm to (%.3f, %.3f) m",
                    self.scene.name,
                    self.robot_names[i],
                    " and ".join(overlaps[i]) or "a robot that was moved out of something",
                    100.0 * moved,
                    pos[i][0],
                    pos[i][1],
                )
        self._poses[:] = pos
        self._contacts[:] = contact
        self._touching = list(contact)

    def _start_overlaps(self, i: int) -> list[str]:
        """What robot ``i`` overlaps at its start pose: static things, then other robots."""
        x, y, _ = self._pose_list[i]
        r = self._body_radius[i]
        found = self.statics.overlapping(x, y, r)
        for j, (xj, yj, _) in enumerate(self._pose_list):
            if j != i and math.hypot(xj - x, yj - y) < r + self._body_radius[j]:
                found.append(f"robot {self.robot_names[j]!r}")
        return found

    # -- Stepper -----------------------------------------------------------------------------
    @property
    def dt(self) -> float:
        return self._dt

    @property
    def time(self) -> float:
        return self._time

    def start(self) -> None:
        self.running = True

    def stop(self) -> None:
        """Stop: wheels commanded to zero. Stepping again resumes from here."""
        with self._lock:
            self.running = False
            self._command = [(0.0, 0.0)] * self.n
            for row in self._due:  # nothing still on its way arrives after a stop
                row[:] = [None] * self.n
            if self._cycles is not None:
                self._cycles.clear()

    def step(self, n: int = 1) -> None:
        """Advance ``n`` steps of ``dt``; sensors then describe the new state."""
        if n < 0:
            raise ValueError(f"cannot step a negative number of times ({n})")
        with self._lock:
            for _ in range(n):
                self._step_once()

    # -- state arrays (read-only views) ------------------------------------------------------
    @property
    def lock(self) -> threading.RLock:
        """Held while the world steps: hold it to read several arrays as one state."""
        return self._lock

    def robot_arrays(self, i: int) -> RobotArrays:
        """Robot ``i``'s rows of every array below, as live read-only views."""
        return self._robot_arrays[i]

    @property
    def poses(self) -> FloatArray:
        """N×3 ground-truth poses (x m, y m, theta rad in (-π, π])."""
        return self._views["poses"]

    @property
    def wheel_speeds(self) -> FloatArray:
        """N×2 actual wheel speeds (rad/s, left/right) of the last step."""
        return self._views["wheel_speeds"]

    @property
    def encoders(self) -> FloatArray:
        """N×2 accumulated wheel rotation (rad)."""
        return self._views["encoders"]

    @property
    def prox_distance(self) -> FloatArray:
        """N×8 IR distances (m, ps0..ps7), converted from the calibrated values as a robot's
        software does (V-REP's cones: exact); exactly the range where nothing is seen."""
        return self._views["prox_distance"]

    @property
    def prox_raw(self) -> FloatArray:
        """N×8 calibrated IR values, as an e-puck sends them (≈0 nothing .. 4095 touching)."""
        return self._views["prox_raw"]

    @property
    def ground(self) -> FloatArray:
        """N×3 ground brightness 0..1 (left, centre, right)."""
        return self._views["ground"]

    @property
    def ground_raw(self) -> FloatArray:
        """N×3 raw ground values on the e-puck scale (0..1023)."""
        return self._views["ground_raw"]

    @property
    def collisions(self) -> npt.NDArray[np.int64]:
        """N collision counts: how many times each robot came into contact with something."""
        return self._views["collisions"]

    @property
    def contacts_now(self) -> npt.NDArray[np.bool_]:
        """N flags: is the robot touching something after the last step."""
        return self._views["contacts_now"]

    @property
    def accelerations(self) -> FloatArray:
        """N×3 accelerometer readings (robot frame, m/s², gravity on z)."""
        return self._views["accelerations"]

    @property
    def angular_velocities(self) -> FloatArray:
        """N×3 gyro readings (robot frame, rad/s): the yaw rate over the last step on z
        (counter-clockwise positive), zero on x and y."""
        return self._views["angular_velocities"]

    def index(self, name: str) -> int:
        """The index of the robot called ``name``."""
        try:
            return self.robot_names.index(name)
        except ValueError:
            raise KeyError(
                f"no robot {name!r} in scene {self.scene.name!r}; robots: {list(self.robot_names)}"
            ) from None

    # -- actuation -----------------------------------------------------------------------------
    def set_wheel_speeds(self, i: int, left: float, right: float) -> None:
        """Command robot ``i``'s wheels (rad/s), clamped to its profile's limit.

        For callers with no adapter in front (the CoppeliaSim stand-in server, the
        emulated e-puck, scripts and tests): their numbers come from anywhere, and the
        motors cannot turn faster than the profile says. An adapter clamps (and warns)
        itself and hands the result to :meth:`drive`.
        """
        limit = self._max_wheel[i]
        self.drive(i, max(-limit, min(limit, float(left))), max(-limit, min(limit, float(right))))

    def drive(self, i: int, left: float, right: float) -> None:
        """Command robot ``i``'s wheels (rad/s, floats) as given, already within its
        profile's limit: the embedded adapter's entry, which clamped once before.

        With a control latency (``scene.control.latency``) the command reaches the
        wheels that many steps later; until then they keep the one before."""
        with self._lock:
            if self._cycles is not None:
                self._cycles.send(i, self.step_count, (left, right))
            elif self._delay:
                self._due[(self.step_count + self._delay) % (self._delay + 1)][i] = (left, right)
            else:
                self._command[i] = (left, right)

    def fresh_reading(self, i: int) -> bool:
        """Whether robot ``i``'s reading this cycle is a new packet: always, unless the
        scene's link repeats readings (``control.repeated``)."""
        return True if self._cycles is None else self._cycles.fresh(i)

    def set_pose(self, i: int, x: float, y: float, theta: float) -> None:
        """Place robot ``i`` (for tests and scripted set-ups); sensors are recomputed."""
        pose = [float(x), float(y), math.remainder(float(theta), math.tau)]
        with self._lock:
            self._pose_list[i] = pose
            self._poses[i] = pose
            self._velocity[i] = (0.0, 0.0)
            self._gyro_z[i] = 0.0
            self.sensing.sense(self._pose_list, None, None)

    def recalibrate_ir(self, i: int) -> None:
        """Robot ``i`` re-measures its IR baselines where it stands, as the e-puck2 firmware
        does on request: in free space that zeroes its sensors' offsets; an object in front
        of a sensor blinds it later. Its readings now are those just after calibrating."""
        with self._lock:
            self.sensing.recalibrate_ir(i, self._pose_list)

    # -- the step ------------------------------------------------------------------------------
    def _step_once(self) -> None:
        n = self.n
        z = self.rng.standard_normal(n * NORMALS_PER_ROBOT) if self._noisy else None
        if self._delay:
            self._deliver()
        elif self._cycles is not None:
            for i in range(n):
                arrived = self._cycles.due(i, self.step_count)
                if arrived is not None:
                    self._command[i] = arrived
        # The e-puck's steppers turn the wheels exactly as commanded; the noise is the
        # ground's: slip makes the body move by (1 + σ·N) of what the wheel turned, and
        # each wheel rolls its own true radius. So the step counters (encoders) and
        # reported wheel speeds follow the command, and odometry drifts as it does on the
        # real robot.
        commanded = list(self._command)
        old = [(p[0], p[1], p[2]) for p in self._pose_list]
        touched = self._move(self._slipped(commanded, z))
        self._update_imu(old)
        self._count_contacts(touched)
        self._poses[:] = self._pose_list
        self._wheels[:] = commanded
        self._encoders += self._wheels * self._dt
        self.step_count += 1
        self._time = self.step_count * self._dt
        t0 = time.perf_counter()
        if z is None:
            self.sensing.sense(self._pose_list, None, None)
        else:
            self.sensing.sense(self._pose_list, z[2 * n : 10 * n].reshape(n, 8), z[10 * n :])
        self.sensor_seconds += time.perf_counter() - t0

    def _deliver(self) -> None:
        """Hand the wheels the commands due at this step (see :meth:`drive`)."""
        due = self._due[self.step_count % (self._delay + 1)]
        for i, command in enumerate(due):
            if command is not None:
                self._command[i] = command
                due[i] = None

    def _slipped(
        self, commanded: list[tuple[float, float]], z: FloatArray | None
    ) -> list[tuple[float, float]]:
        """The wheel speeds the ground lets act on the body: the command times (1 + σ·N)."""
        if z is None or self._noise_wheel <= 0:
            return commanded
        zw = z[: 2 * self.n].tolist()
        sigma = self._noise_wheel
        out = []
        for i, (left, right) in enumerate(commanded):
            limit = self._max_wheel[i]
            left = left * (1.0 + sigma * zw[2 * i])
            right = right * (1.0 + sigma * zw[2 * i + 1])
            out.append(
                (
                    -limit if left < -limit else limit if left > limit else left,
                    -limit if right < -limit else limit if right > limit else right,
                )
            )
        return out

    def _move(self, wheels: list[tuple[float, float]]) -> list[bool]:
        """Move every robot along its arc in contact-safe sub-steps; who touched something."""
        n, dt = self.n, self._dt
        poses = self._pose_list
        forward = [0.0] * n
        turn = [0.0] * n
        for i, (left_wheel, right_wheel) in enumerate(wheels):
            radius_left, radius_right = self._wheel_radii[i]
            left = left_wheel * radius_left
            right = right_wheel * radius_right
            forward[i] = 0.5 * (left + right)
            turn[i] = (right - left) / self._axle[i]
        fastest = max(abs(v) for v in forward) * dt
        substeps = max(1, math.ceil(fastest / self._max_substep_move))
        h = dt / substeps
        touched = [False] * n
        for _ in range(substeps):
            for i in range(n):
                p = poses[i]
                p[0], p[1], p[2] = arc(p[0], p[1], p[2], forward[i], turn[i], h)
            contact = self.statics.resolve(poses, self._body_radius)
            touched = [a or b for a, b in zip(touched, contact)]
        return touched

    def _update_imu(self, old: list[tuple[float, float, float]]) -> None:
        """Accelerometers and gyros from the step's actual (contact-limited) motion.

        Accelerometer: change of the velocity, in the robot frame; gyro: change of the
        heading (exact while a step turns less than π).
        """
        inv_dt = 1.0 / self._dt
        velocity = self._velocity
        accel = []
        yaw_rate = []
        for i, p in enumerate(self._pose_list):
            vx = (p[0] - old[i][0]) * inv_dt
            vy = (p[1] - old[i][1]) * inv_dt
            ax = (vx - velocity[i][0]) * inv_dt
            ay = (vy - velocity[i][1]) * inv_dt
            velocity[i] = (vx, vy)
            c, s = math.cos(p[2]), math.sin(p[2])
            accel.append((ax * c + ay * s, -ax * s + ay * c, GRAVITY))
            yaw_rate.append(math.remainder(p[2] - old[i][2], math.tau) * inv_dt)
        if self._noise_gyro > 0:
            yaw_rate = (self._noise_gyro * self.rng.standard_normal(self.n) + yaw_rate).tolist()
        if self._gyro_bias != 0.0:
            yaw_rate = [w + self._gyro_bias for w in yaw_rate]
        self._accel[:] = accel
        self._gyro_z[:] = yaw_rate

    def _count_contacts(self, touched: list[bool]) -> None:
        """Contact flags, and a collision counted for each robot that newly touches
        something (both change rarely: the arrays are written only when they do)."""
        if touched == self._touching:
            return
        for i, (now, before) in enumerate(zip(touched, self._touching)):
            if now and not before:
                self._collisions[i] += 1
        self._contacts[:] = touched
        self._touching = touched

    # -- camera --------------------------------------------------------------------------------
    def render_camera(self, i: int, size: tuple[int, int] | None = None) -> npt.NDArray[np.uint8]:
        """Robot ``i``'s camera pixels, a fresh H×W×3 uint8 array (``size`` = (width,
        height), default the scene's)."""
        with self._lock:
            return self._cameras.render(i, self._poses, size)

    def __repr__(self) -> str:
        return (
            f"<World {self.scene.name!r} robots={list(self.robot_names)} "
            f"t={self._time:.3f}s seed={self.seed}>"
        )
