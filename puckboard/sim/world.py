"""The embedded simulator's world: robots, floor, obstacles, walls, sensors, one clock.

A :class:`World` is built from a :class:`~puckboard.scenario.scene.Scene` and stepped
synchronously (it satisfies the stepping protocol, :class:`~puckboard.backends.base.Stepper`, every embedded robot
shares). Each :meth:`World.step`:

1. turns each robot's wheel command into actual wheel speeds (clamped to the profile's
   limit, times ``1 + σ·N(0, 1)`` wheel-speed noise);
2. moves every robot along its exact arc (:mod:`.kinematics`), in sub-steps short enough
   that nothing can tunnel, resolving contacts after each (:mod:`.contacts`);
3. computes every sensor of every robot in a few vectorised numpy calls: all IR rays of
   all robots near something in one cast (:mod:`.proximity`), all ground sensors in one
   query of the nearby track segments (:mod:`.floor`), accelerometers from the velocity
   change, gyros from the heading change.

The results live in N×k arrays (``poses``, ``prox_distance``, ``ground`` ...); records
are only created when an adapter calls :meth:`World.read`. The camera is rendered on
demand (:meth:`World.camera`) and is noise-free, so rendering never changes a run.

Randomness: one ``np.random.Generator(PCG64(seed))`` per world draws the start-pose
jitter at construction and then, each step, one block of normals for the wheels, the IR
sensors and the ground sensors, always the same number whatever is read, so the same
seed gives the same arrays with or without a viewer. Gyro noise, when the scene sets
some, is one more block of N normals per step after it.

See docs/simulator.md for every model's source and the choices made.
"""

from __future__ import annotations

import logging
import math
import threading
import time
from collections.abc import Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from ..profile import RobotProfile, get_profile
from ..records import (
    GRAVITY,
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
from ..scenario.scene import CircleObstacle, PolygonObstacle, Scene
from .camera import CameraRenderer
from .cone import ConeSensors
from .contacts import Statics
from .floor import Floor
from .kinematics import arc
from .proximity import PolygonBound, ProximitySensors, WallSegment

__all__ = ["IR_RAYS", "OBSTACLE_HEIGHT", "ROBOT_HEIGHT", "WALL_HEIGHT", "World"]

log = logging.getLogger(__name__)

FloatArray = npt.NDArray[np.float64]

#: Rays cast per IR sensor, spread evenly across the sensor's aperture.
IR_RAYS = 5
#: Heights (m) used by the camera: scenes are 2D, the camera needs a third dimension.
ROBOT_HEIGHT = 0.05
OBSTACLE_HEIGHT = 0.06
WALL_HEIGHT = 0.08
#: Largest distance (as a fraction of the body radius) a robot may move in one physics
#: sub-step; longer steps are split so contacts are never skipped.
MAX_SUBSTEP_FRACTION = 0.25


class World:
    """A simulated scene; see the module docstring.

    ``ir_rays`` rays per IR sensor (odd, so one looks straight ahead) and
    ``ground_footprint`` (m, half-width of a ground sensor's spot) tune the sensor
    models; the defaults are documented in docs/simulator.md.
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
        self.profiles: tuple[RobotProfile, ...] = tuple(
            get_profile(r.profile) for r in scene.robots
        )
        n = len(scene.robots)
        self.n = n
        prof = self.profiles
        self._wheel_radius = np.array([p.wheel_radius for p in prof])
        self._axle = np.array([p.axle_length for p in prof])
        self._max_wheel = np.array([p.max_wheel_speed for p in prof])
        self._radius = np.array([p.body_radius for p in prof])
        self._radius_list = self._radius.tolist()
        self._range = np.array([p.prox_range for p in prof])
        noise = scene.noise
        self._noise_wheel = float(noise.wheel_speed)
        self._noise_prox = float(noise.proximity)
        self._noise_ground = float(noise.ground)
        self._noisy = self._noise_wheel > 0 or self._noise_prox > 0 or self._noise_ground > 0
        self._noise_gyro = float(noise.gyro)
        self._gyro_bias = float(noise.gyro_bias)

        self._init_state()

        # -- static geometry ------------------------------------------------------------
        self.floor = (
            Floor(scene) if ground_footprint is None else Floor(scene, footprint=ground_footprint)
        )
        self.statics = Statics(scene.obstacles, scene.arena)
        self._build_geometry()
        self._build_sensor_layout(ir_rays)

        self._init_sensor_buffer()
        # the first contact check and sensor pass describe the start pose (time 0)
        self._resolve_start_contacts()
        self._sense(None)
        self._cameras: dict[tuple[int, int, float, float], CameraRenderer] = {}
        self._read_only_views()

    # -- construction helpers ----------------------------------------------------------------
    def _init_state(self) -> None:
        """The robots' moving state: poses (with start jitter), wheels, encoders, IMU."""
        scene, n, noise = self.scene, self.n, self.scene.noise
        self._poses = np.array([[r.x, r.y, r.theta] for r in scene.robots], dtype=float)
        if noise.start_jitter > 0:
            self._poses += self.rng.normal(0.0, noise.start_jitter, size=(n, 3))
        self._poses[:, 2] = np.remainder(self._poses[:, 2] + math.pi, math.tau) - math.pi
        # wheel commands as plain floats: set once per robot per cycle, read once per step
        self._command: list[list[float]] = [[0.0, 0.0] for _ in range(n)]
        self._wheels = np.zeros((n, 2))
        self._encoders = np.zeros((n, 2))
        self._accel = np.zeros((n, 3))
        self._accel[:, 2] = GRAVITY
        # gyro: a planar world turns only about z, so x and y stay zero
        self._gyro = np.zeros((n, 3))
        self._gyro_z = self._gyro[:, 2]
        self._collisions = np.zeros(n, dtype=np.int64)
        self._contacts = np.zeros(n, dtype=bool)
        # the step works on plain Python floats (cheaper than numpy for a few robots) and
        # copies them into the arrays above once per step
        self._wheel_radius_list = self._wheel_radius.tolist()
        self._axle_list = self._axle.tolist()
        self._max_wheel_list = self._max_wheel.tolist()
        self._max_substep_move = MAX_SUBSTEP_FRACTION * min(self._radius_list)
        self._pose_list: list[list[float]] = self._poses.tolist()
        self._velocity_list: list[tuple[float, float]] = [(0.0, 0.0)] * n
        self._accel_list: list[list[float]] = self._accel.tolist()
        self._yaw_rate_list: list[float] = [0.0] * n
        self._encoder_list: list[list[float]] = self._encoders.tolist()
        self._contact_list: list[bool] = [False] * n
        self._wheel_list: list[list[float]] = [[0.0, 0.0] for _ in range(n)]
        self._range_list: list[float] = self._range.tolist()
        self._collision_list: list[int] = [0] * n

    def _init_sensor_buffer(self) -> None:
        """One buffer for all sensor arrays; see the comment below for why."""
        n = self.n
        # The four sensor arrays are consecutive blocks of one buffer (each still a
        # contiguous N×k array); a record's row is a slice of it, which the record's
        # constructor copies.
        blocks = (("prox_distance", 8), ("prox_raw", 8), ("ground", 3), ("ground_raw", 3))
        self._sensor_buffer = np.zeros(n * sum(k for _, k in blocks))
        views = {}
        rows: list[dict[str, slice]] = [{} for _ in range(n)]
        start = 0
        for name, k in blocks:
            views[name] = self._sensor_buffer[start : start + n * k].reshape(n, k)
            for i in range(n):
                rows[i][name] = slice(start + i * k, start + (i + 1) * k)
            start += n * k
        self._prox_distance = views["prox_distance"]
        self._prox_raw = views["prox_raw"]
        self._ground = views["ground"]
        self._ground_raw = views["ground_raw"]
        self._ground_flat = self._ground.reshape(-1)  # views, written in place
        self._ground_raw_flat = self._ground_raw.reshape(-1)
        self._sensor_rows = rows

    def _build_geometry(self) -> None:
        """Stack every static surface once: segments (polygon edges, walls) and circles."""
        scene = self.scene
        starts: list[FloatArray] = []
        vectors: list[FloatArray] = []
        seg_colours: list[tuple[int, int, int]] = []
        seg_heights: list[float] = []
        circles: list[tuple[float, float, float]] = []
        circle_colours: list[tuple[int, int, int]] = []
        for ob in scene.obstacles:
            if isinstance(ob, PolygonObstacle):
                a, e = ob.edges()
                starts.append(a)
                vectors.append(e)
                seg_colours += [ob.colour] * len(a)
                seg_heights += [OBSTACLE_HEIGHT] * len(a)
            elif isinstance(ob, CircleObstacle):
                circles.append((ob.x, ob.y, ob.radius))
                circle_colours.append(ob.colour)
        if scene.arena is not None:
            ar = scene.arena
            a, e = ar.edges()
            starts.append(a)
            vectors.append(e)
            seg_colours += [ar.colour] * 4
            seg_heights += [WALL_HEIGHT] * 4
        # bounding data for the IR broad phase: polygons (bounding circle and their
        # edges' indices) and walls (each wall segment tested exactly)
        self._static_circles = [(float(c[0]), float(c[1]), float(c[2])) for c in circles]
        polygons: list[PolygonBound] = []
        walls: list[WallSegment] = []
        first = 0
        for ob in scene.obstacles:
            if isinstance(ob, PolygonObstacle):
                v = np.asarray(ob.vertices, dtype=float)
                centre = v.mean(axis=0)
                radius = float(np.hypot(*(v - centre).T).max())
                idx = tuple(range(first, first + len(v)))
                polygons.append(PolygonBound(float(centre[0]), float(centre[1]), radius, idx))
                first += len(v)
        if scene.arena is not None:
            for k in range(4):
                ax, ay = starts[-1][k].tolist()
                ex, ey = vectors[-1][k].tolist()
                walls.append(WallSegment(ax, ay, ex, ey, first + k))
        self._polygon_bounds = polygons
        self._wall_segments = walls
        self._seg_start = np.vstack(starts) if starts else np.zeros((0, 2))
        self._seg_vector = np.vstack(vectors) if vectors else np.zeros((0, 2))
        n_static = len(circles)
        self._n_static_circles = n_static
        # circles: static obstacles first, then one per robot (centres updated each step)
        self._circle_centres = np.zeros((n_static + self.n, 2))
        if circles:
            self._circle_centres[:n_static] = np.array(circles)[:, :2]
        self._circle_radii = np.concatenate(
            [np.array([c[2] for c in circles], dtype=float), self._radius]
        )
        robot_colours = [r.colour for r in scene.robots]
        self._object_colours = np.array(
            seg_colours + circle_colours + robot_colours, dtype=np.uint8
        ).reshape(-1, 3)
        self._object_heights = np.array(
            seg_heights + [OBSTACLE_HEIGHT] * n_static + [ROBOT_HEIGHT] * self.n, dtype=float
        )

    def _build_sensor_layout(self, rays: int) -> None:
        """The IR sensor array, and the ground sensors' local positions."""
        for p in self.profiles:
            if len(p.ground_poses) != 3:
                raise ValueError(f"profile {p.name!r} must have 3 ground sensor poses")
        self.proximity = ProximitySensors(
            self.profiles,
            rays=rays,
            seg_start=self._seg_start,
            seg_vector=self._seg_vector,
            static_circles=self._static_circles,
            polygons=self._polygon_bounds,
            walls=self._wall_segments,
        )
        # robots whose profile senses as V-REP does: exact cones, computed after the rays
        cone_robots = [i for i, p in enumerate(self.profiles) if p.prox_model == "cone"]
        self.cones = ConeSensors(
            self.profiles,
            cone_robots,
            static_circles=self._static_circles,
            seg_start=self._seg_start,
            seg_vector=self._seg_vector,
        )
        # ground sensors: local positions, and their centroid for the segment grid
        self._ground_local = [[(q.x, q.y) for q in p.ground_poses] for p in self.profiles]
        self._ground_mid = [
            (sum(q[0] for q in g) / len(g), sum(q[1] for q in g) / len(g))
            for g in self._ground_local
        ]
        self._ground_reach = max(
            math.hypot(q[0] - m[0], q[1] - m[1])
            for g, m in zip(self._ground_local, self._ground_mid)
            for q in g
        )
        self._no_track = self.floor.seg_start.shape[0] == 0
        self._floor_values = self.floor.brightness_values(np.zeros((3 * self.n, 2)))

    def _read_only_views(self) -> None:
        def ro(a: np.ndarray) -> np.ndarray:
            v = a.view()
            v.flags.writeable = False
            return v

        self._views = {
            "poses": ro(self._poses),
            "wheel_speeds": ro(self._wheels),
            "encoders": ro(self._encoders),
            "prox_distance": ro(self._prox_distance),
            "prox_raw": ro(self._prox_raw),
            "ground": ro(self._ground),
            "collisions": ro(self._collisions),
            "contacts_now": ro(self._contacts),
            "accelerations": ro(self._accel),
            "angular_velocities": ro(self._gyro),
        }

    def _resolve_start_contacts(self) -> None:
        pos = self._pose_list
        contact = self.statics.resolve(pos, self._radius_list)
        moved = float(np.abs(np.array(pos) - self._poses).max())
        if moved > 1e-9:
            log.warning(
                "scene %r: a robot starts overlapping something; moved it by %.4f m",
                self.scene.name,
                moved,
            )
        self._poses[:] = pos
        self._contacts[:] = contact
        self._contact_list = list(contact)

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
            self._command = [[0.0, 0.0] for _ in range(self.n)]

    def step(self, n: int = 1) -> None:
        """Advance ``n`` steps of ``dt``; sensors then describe the new state."""
        if n < 0:
            raise ValueError(f"cannot step a negative number of times ({n})")
        with self._lock:
            for _ in range(n):
                self._step_once()

    # -- state arrays (read-only views) ------------------------------------------------------
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
        """N×8 IR distances (m, ps0..ps7); exactly the range where nothing is seen."""
        return self._views["prox_distance"]

    @property
    def prox_raw(self) -> FloatArray:
        """N×8 raw IR values on the e-puck scale (≈67 nothing .. 4095 touching)."""
        return self._views["prox_raw"]

    @property
    def ground(self) -> FloatArray:
        """N×3 ground brightness 0..1 (left, centre, right)."""
        return self._views["ground"]

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
        """Command robot ``i``'s wheels (rad/s), clamped to its profile's limit."""
        limit = self._max_wheel_list[i]
        # a new list, never one changed in place: the last step's records share the old one
        command = [max(-limit, min(limit, float(left))), max(-limit, min(limit, float(right)))]
        with self._lock:
            self._command[i] = command

    def set_pose(self, i: int, x: float, y: float, theta: float) -> None:
        """Place robot ``i`` (for tests and scripted set-ups); sensors are recomputed."""
        pose = [float(x), float(y), math.remainder(float(theta), math.tau)]
        with self._lock:
            self._pose_list[i] = pose
            self._poses[i] = pose
            self._velocity_list[i] = (0.0, 0.0)
            self._yaw_rate_list[i] = 0.0
            self._gyro_z[i] = 0.0
            self._sense(None)

    # -- the step ------------------------------------------------------------------------------
    def _step_once(self) -> None:
        n = self.n
        z = self.rng.standard_normal(n * 13) if self._noisy else None
        # The e-puck's steppers turn the wheels exactly as commanded; the noise is the
        # ground's: slip makes the body move by (1 + σ·N) of what the wheel turned. So the
        # step counters (encoders) and reported wheel speeds follow the command, and
        # odometry drifts as it does on the real robot.
        stepped = list(self._command)
        old = [(p[0], p[1], p[2]) for p in self._pose_list]
        touched = self._move(self._slipped(stepped, z))
        new_collision = self._update_inertial_and_counters(old, stepped, touched)
        self._publish(stepped, touched, new_collision)
        t0 = time.perf_counter()
        self._sense(z)
        self.sensor_seconds += time.perf_counter() - t0

    def _slipped(self, stepped: list[list[float]], z: FloatArray | None) -> list[list[float]]:
        """The wheel speeds the ground lets act on the body: the command times (1 + σ·N)."""
        command = [list(c) for c in stepped]
        if z is not None and self._noise_wheel > 0:
            zw = z[: 2 * self.n].tolist()
            sigma = self._noise_wheel
            for i in range(self.n):
                limit = self._max_wheel_list[i]
                left = command[i][0] * (1.0 + sigma * zw[2 * i])
                right = command[i][1] * (1.0 + sigma * zw[2 * i + 1])
                command[i] = [
                    -limit if left < -limit else limit if left > limit else left,
                    -limit if right < -limit else limit if right > limit else right,
                ]
        return command

    def _move(self, command: list[list[float]]) -> list[bool]:
        """Move every robot along its arc in contact-safe sub-steps; who touched something."""
        n, dt = self.n, self._dt
        poses = self._pose_list
        forward = [0.0] * n
        turn = [0.0] * n
        for i in range(n):
            left = command[i][0] * self._wheel_radius_list[i]
            right = command[i][1] * self._wheel_radius_list[i]
            forward[i] = 0.5 * (left + right)
            turn[i] = (right - left) / self._axle_list[i]
        fastest = max(abs(v) for v in forward) * dt
        substeps = max(1, math.ceil(fastest / self._max_substep_move))
        h = dt / substeps
        touched = [False] * n
        for _ in range(substeps):
            for i in range(n):
                p = poses[i]
                p[0], p[1], p[2] = arc(p[0], p[1], p[2], forward[i], turn[i], h)
            contact = self.statics.resolve(poses, self._radius_list)
            touched = [a or b for a, b in zip(touched, contact)]
        return touched

    def _update_inertial_and_counters(
        self,
        old: list[tuple[float, float, float]],
        stepped: list[list[float]],
        touched: list[bool],
    ) -> bool:
        """Accelerometer, yaw rate, encoders and collision counts; True on a new collision.

        Accelerometer: change of the actual (contact-limited) velocity, in the robot frame;
        gyro: change of the actual heading (exact while a step turns less than π).
        """
        dt = self._dt
        inv_dt = 1.0 / dt
        poses = self._pose_list
        accel = self._accel_list
        yaw_rate = [0.0] * self.n
        velocity = self._velocity_list
        encoders = self._encoder_list
        new_collision = False
        for i in range(self.n):
            p = poses[i]
            vx = (p[0] - old[i][0]) * inv_dt
            vy = (p[1] - old[i][1]) * inv_dt
            ax = (vx - velocity[i][0]) * inv_dt
            ay = (vy - velocity[i][1]) * inv_dt
            velocity[i] = (vx, vy)
            c, s = math.cos(p[2]), math.sin(p[2])
            accel[i] = [ax * c + ay * s, -ax * s + ay * c, GRAVITY]
            yaw_rate[i] = math.remainder(p[2] - old[i][2], math.tau) * inv_dt
            encoders[i][0] += stepped[i][0] * dt
            encoders[i][1] += stepped[i][1] * dt
            if touched[i] and not self._contact_list[i]:
                self._collision_list[i] += 1
                new_collision = True
        if self._noise_gyro > 0:
            yaw_rate = (self._noise_gyro * self.rng.standard_normal(self.n) + yaw_rate).tolist()
        if self._gyro_bias != 0.0:
            yaw_rate = [w + self._gyro_bias for w in yaw_rate]
        self._yaw_rate_list = yaw_rate
        return new_collision

    def _publish(
        self, stepped: list[list[float]], touched: list[bool], new_collision: bool
    ) -> None:
        """Copy the step's state into the read-only arrays in a few bulk copies (contacts
        and collision counts change rarely: copied only when they do)."""
        self._poses[:] = self._pose_list
        self._wheels[:] = stepped
        self._wheel_list = stepped
        self._encoders[:] = self._encoder_list
        self._accel[:] = self._accel_list
        self._gyro_z[:] = self._yaw_rate_list
        if touched != self._contact_list:
            self._contacts[:] = touched
        self._contact_list = touched
        if new_collision:
            self._collisions[:] = self._collision_list
        self.step_count += 1
        self._time = self.step_count * self._dt

    def _sense(self, z: FloatArray | None) -> None:
        """All IR and ground sensors of all robots for the current poses."""
        n = self.n
        # -- IR: the rays of every robot near something, in one cast ----------------------
        self.proximity.sense(
            self._pose_list,
            self._prox_distance,
            self._prox_raw,
            noise=self._noise_prox,
            z=None if z is None else z[2 * n : 10 * n].reshape(n, 8),
        )
        self.cones.sense(
            self._pose_list,
            self._prox_distance,
            self._prox_raw,
            near=self.proximity.cones_near,
            candidates=self.proximity.cone_candidates,
        )
        # -- ground: only the track segments near the robots ------------------------------
        if self._no_track:
            # no line on the floor (the swarm's arena): every sensor sees the floor, as
            # the search below would find with no segment near any point
            values = self._floor_values
        else:
            # three points per robot: plain floats are cheaper than a dozen numpy calls
            points: list[complex] = []
            centres = []
            for i, (x, y, th) in enumerate(self._pose_list):
                c, s = math.cos(th), math.sin(th)
                for lx, ly in self._ground_local[i]:
                    points.append(complex(x + c * lx - s * ly, y + s * lx + c * ly))
                mx, my = self._ground_mid[i]
                centres.append((x + c * mx - s * my, y + s * mx + c * my))
            near = self.floor.segments_near(centres, self._ground_reach)
            values = self.floor.brightness_values(np.array(points), near)
        # The 3N readings stay flat (robot-major, as the N×3 arrays store them). Noise,
        # clamping and the raw scale are a few float operations per reading: plain
        # floats, in the order the arrays would apply them, cost less than numpy calls.
        if z is not None and self._noise_ground > 0:
            sigma = self._noise_ground
            values = [v + sigma * zk for v, zk in zip(values, z[10 * n : 13 * n].tolist())]
        values = [0.0 if v < 0.0 else 1.0 if v > 1.0 else v for v in values]
        self._ground_flat[:] = values
        self._ground_raw_flat[:] = [v * 1023.0 for v in values]

    # -- records -------------------------------------------------------------------------------
    def read(self, i: int, sensors: frozenset[Sensor] | Sequence[Sensor]) -> dict[Sensor, Any]:
        """Records of robot ``i``'s ``sensors`` from the latest step.

        The embedded robot has no light sensor model (no light sources in a scene):
        asking for :attr:`Sensor.LIGHT` or the camera here is an error; use
        :meth:`camera` for images.
        """
        with self._lock:
            return self._records(i, sensors)

    def _records(self, i: int, sensors: frozenset[Sensor] | Sequence[Sensor]) -> dict[Sensor, Any]:
        # Array records are given views of the live sensor buffer: their constructors
        # copy the values into read-only arrays of their own, so a later step cannot
        # change a record already handed out.
        out: dict[Sensor, Any] = {}
        buffer = self._sensor_buffer
        rows = self._sensor_rows[i]
        for sensor in sensors:
            if sensor is Sensor.PROXIMITY:
                out[sensor] = Proximity(
                    distance=buffer[rows["prox_distance"]],
                    raw=buffer[rows["prox_raw"]],
                    range=self._range_list[i],
                )
            elif sensor is Sensor.GROUND:
                out[sensor] = Ground(value=buffer[rows["ground"]], raw=buffer[rows["ground_raw"]])
            elif sensor is Sensor.POSE:
                x, y, theta = self._pose_list[i]
                out[sensor] = Pose(x=x, y=y, theta=theta, ground_truth=True)
            elif sensor is Sensor.ENCODERS:
                left, right = self._encoder_list[i]
                out[sensor] = WheelEncoders(left=left, right=right)
            elif sensor is Sensor.WHEEL_SPEEDS:
                left, right = self._wheel_list[i]
                out[sensor] = WheelSpeeds(left=left, right=right)
            elif sensor is Sensor.ACCELERATION:
                ax, ay, az = self._accel_list[i]
                out[sensor] = Acceleration(x=ax, y=ay, z=az)
            elif sensor is Sensor.GYRO:
                out[sensor] = AngularVelocity(x=0.0, y=0.0, z=self._yaw_rate_list[i])
            else:
                raise ValueError(
                    f"the embedded simulator has no {Sensor(sensor).value} sensor in read(); "
                    "use camera(i) for images"
                )
        return out

    def camera(self, i: int, size: tuple[int, int] | None = None) -> CameraImage:
        """Robot ``i``'s camera image (``size`` = (width, height), default the scene's)."""
        pixels = self.render_camera(i, size)
        pixels.flags.writeable = False
        return CameraImage(pixels=pixels)

    def render_camera(self, i: int, size: tuple[int, int] | None = None) -> npt.NDArray[np.uint8]:
        """The camera pixels (a fresh H×W×3 uint8 array) without wrapping them in a record."""
        with self._lock:
            return self._render(i, size)

    def _render(self, i: int, size: tuple[int, int] | None) -> npt.NDArray[np.uint8]:
        width, height = size if size is not None else self.scene.camera_size
        profile = self.profiles[i]
        key = (int(width), int(height), profile.camera_fov, profile.camera_height)
        renderer = self._cameras.get(key)
        if renderer is None:
            renderer = CameraRenderer(
                self.floor,
                width=int(width),
                height=int(height),
                fov=profile.camera_fov,
                camera_height=profile.camera_height,
                object_colours=self._object_colours,
                object_heights=self._object_heights,
            )
            self._cameras[key] = renderer
        self._circle_centres[self._n_static_circles :] = self._poses[:, :2]
        x, y, th = self._poses[i].tolist()
        return renderer.render(
            x,
            y,
            th,
            self._seg_start,
            self._seg_vector,
            self._circle_centres,
            self._circle_radii,
            ignore_circle=self._n_static_circles + i,
        )

    def __repr__(self) -> str:
        return (
            f"<World {self.scene.name!r} robots={list(self.robot_names)} "
            f"t={self._time:.3f}s seed={self.seed}>"
        )
