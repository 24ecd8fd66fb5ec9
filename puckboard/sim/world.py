"""The embedded simulator's world: robots, floor, obstacles, walls, sensors, one clock.

A :class:`World` is built from a :class:`~puckboard.sim.scene.Scene` and stepped
synchronously (it is the :class:`~puckboard.adapters.base.Stepper` every embedded robot
shares). Each :meth:`World.step`:

1. turns each robot's wheel command into actual wheel speeds (clamped to the profile's
   limit, times ``1 + σ·N(0, 1)`` wheel-speed noise);
2. moves every robot along its exact arc (:mod:`.kinematics`), in sub-steps short enough
   that nothing can tunnel, resolving contacts after each (:mod:`.contacts`);
3. computes every sensor of every robot in a few vectorised numpy calls: all IR rays of
   all robots in one :func:`~puckboard.sim.geometry.cast_rays`, all ground sensors in one
   floor query, accelerometers from the velocity change.

The results live in N×k arrays (``poses``, ``prox_distance``, ``ground`` ...); records
are only created when an adapter calls :meth:`World.read`. The camera is rendered on
demand (:meth:`World.camera`) and is noise-free, so rendering never changes a run.

Randomness: one ``np.random.Generator(PCG64(seed))`` per world draws the start-pose
jitter at construction and then, each step, one block of normals for the wheels, the IR
sensors and the ground sensors, always the same number whatever is read, so the same
seed gives the same arrays with or without a viewer.

See docs/simulator.md for every model's source and the choices made.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from ..adapters.base import Stepper
from ..profile import RobotProfile, get_profile
from ..records import (
    Acceleration,
    CameraImage,
    Ground,
    Pose,
    Proximity,
    Sensor,
    WheelEncoders,
    WheelSpeeds,
)
from .camera import CameraRenderer
from .contacts import Statics
from .floor import Floor
from .geometry import cast_rays, polygon_edges
from .ir import RAW_MAX, TABLE_RANGE, raw_from_distance, relative_sigma
from .kinematics import arc_step, body_velocity
from .scene import CircleObstacle, PolygonObstacle, Scene

__all__ = ["GRAVITY", "IR_RAYS", "OBSTACLE_HEIGHT", "ROBOT_HEIGHT", "WALL_HEIGHT", "World"]

log = logging.getLogger(__name__)

FloatArray = npt.NDArray[np.float64]

GRAVITY = 9.81
#: Rays cast per IR sensor, spread evenly across the sensor's aperture.
IR_RAYS = 5
#: Heights (m) used by the camera: scenes are 2D, the camera needs a third dimension.
ROBOT_HEIGHT = 0.05
OBSTACLE_HEIGHT = 0.06
WALL_HEIGHT = 0.08
#: Largest distance (as a fraction of the body radius) a robot may move in one physics
#: sub-step; longer steps are split so contacts are never skipped.
MAX_SUBSTEP_FRACTION = 0.25


class World(Stepper):
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
        if ir_rays < 1:
            raise ValueError(f"ir_rays must be at least 1, got {ir_rays}")
        self.scene = scene
        self.seed = seed
        self.rng = np.random.Generator(np.random.PCG64(seed))
        self._dt = float(scene.dt)
        self._time = 0.0
        self.step_count = 0
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

        # -- state ----------------------------------------------------------------------
        self._poses = np.array([[r.x, r.y, r.theta] for r in scene.robots], dtype=float)
        if noise.start_jitter > 0:
            self._poses += self.rng.normal(0.0, noise.start_jitter, size=(n, 3))
        self._poses[:, 2] = np.remainder(self._poses[:, 2] + math.pi, math.tau) - math.pi
        self._command = np.zeros((n, 2))
        self._wheels = np.zeros((n, 2))
        self._encoders = np.zeros((n, 2))
        self._velocity = np.zeros((n, 2))  # world frame, m/s
        self._accel = np.zeros((n, 3))
        self._accel[:, 2] = GRAVITY
        self._collisions = np.zeros(n, dtype=np.int64)
        self._contacts = np.zeros(n, dtype=bool)

        # -- static geometry ------------------------------------------------------------
        self.floor = (
            Floor(scene) if ground_footprint is None else Floor(scene, footprint=ground_footprint)
        )
        self.statics = Statics(scene.obstacles, scene.arena)
        self._build_geometry()
        self._build_sensor_layout(ir_rays)

        self._prox_distance = np.zeros((n, 8))
        self._prox_raw = np.zeros((n, 8))
        self._ground = np.zeros((n, 3))
        self._ground_raw = np.zeros((n, 3))
        # the first contact check and sensor pass describe the start pose (time 0)
        self._resolve_start_contacts()
        self._sense(None)
        self._cameras: dict[tuple[int, int, float, float], CameraRenderer] = {}
        self._read_only_views()

    # -- construction helpers ----------------------------------------------------------------
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
                a, e = polygon_edges(ob.vertices)
                starts.append(a)
                vectors.append(e)
                seg_colours += [ob.colour] * len(a)
                seg_heights += [OBSTACLE_HEIGHT] * len(a)
            elif isinstance(ob, CircleObstacle):
                circles.append((ob.x, ob.y, ob.radius))
                circle_colours.append(ob.colour)
        if scene.arena is not None:
            ar = scene.arena
            corners = np.array(
                [[ar.xmin, ar.ymin], [ar.xmax, ar.ymin], [ar.xmax, ar.ymax], [ar.xmin, ar.ymax]]
            )
            a, e = polygon_edges(corners)
            starts.append(a)
            vectors.append(e)
            seg_colours += [ar.colour] * 4
            seg_heights += [WALL_HEIGHT] * 4
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

    def _build_sensor_layout(self, k: int) -> None:
        """Per-ray local origins and angles for every robot's IR sensors, ground points."""
        n = self.n
        self._ir_rays = k
        origin_x = np.zeros((n, 8 * k))
        origin_y = np.zeros((n, 8 * k))
        angle = np.zeros((n, 8 * k))
        weights = np.zeros((n, 8, k))
        ground_x = np.zeros((n, 3))
        ground_y = np.zeros((n, 3))
        for i, p in enumerate(self.profiles):
            if len(p.prox_poses) != 8 or len(p.ground_poses) != 3:
                raise ValueError(
                    f"profile {p.name!r} must have 8 proximity and 3 ground sensor poses"
                )
            offsets = (
                np.linspace(-p.prox_aperture / 2, p.prox_aperture / 2, k) if k > 1 else np.zeros(1)
            )
            # Webots combines a sensor's rays with Gaussian weights; σ = aperture/4 puts
            # the outermost rays at two standard deviations.
            sigma = max(p.prox_aperture / 4.0, 1e-9)
            w = np.exp(-0.5 * (offsets / sigma) ** 2)
            for s, pose in enumerate(p.prox_poses):
                origin_x[i, s * k : (s + 1) * k] = pose.x
                origin_y[i, s * k : (s + 1) * k] = pose.y
                angle[i, s * k : (s + 1) * k] = pose.heading + offsets
                weights[i, s] = w / w.sum()
            for g, pose in enumerate(p.ground_poses):
                ground_x[i, g] = pose.x
                ground_y[i, g] = pose.y
        self._ray_ox, self._ray_oy, self._ray_angle = origin_x, origin_y, angle
        self._ray_weights = weights
        self._ground_lx, self._ground_ly = ground_x, ground_y
        # a robot's rays never see its own body (its sensors sit inside the body circle)
        n_circ = self._circle_centres.shape[0]
        ignore = np.zeros((n, 8 * k, n_circ), dtype=bool)
        for i in range(n):
            ignore[i, :, self._n_static_circles + i] = True
        self._ray_ignore = ignore.reshape(n * 8 * k, n_circ)
        self._cast_length = max(TABLE_RANGE, float(self._range.max()))

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
        }

    def _resolve_start_contacts(self) -> None:
        pos = self._poses[:, :2].tolist()
        contact = self.statics.resolve(pos, self._radius_list)
        if any(contact):
            moved = np.abs(np.array(pos) - self._poses[:, :2]).max()
            if moved > 1e-9:
                log.warning(
                    "scene %r: a robot starts overlapping something; moved it by %.4f m",
                    self.scene.name,
                    moved,
                )
            self._poses[:, :2] = pos
        self._contacts[:] = contact

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
        self.running = False
        self._command[:] = 0.0

    def step(self, n: int = 1) -> None:
        """Advance ``n`` steps of ``dt``; sensors then describe the new state."""
        if n < 0:
            raise ValueError(f"cannot step a negative number of times ({n})")
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
        limit = self.profiles[i].max_wheel_speed
        self._command[i, 0] = max(-limit, min(limit, float(left)))
        self._command[i, 1] = max(-limit, min(limit, float(right)))

    def set_pose(self, i: int, x: float, y: float, theta: float) -> None:
        """Place robot ``i`` (for tests and scripted set-ups); sensors are recomputed."""
        self._poses[i] = (x, y, math.remainder(theta, math.tau))
        self._velocity[i] = 0.0
        self._sense(None)

    # -- the step ------------------------------------------------------------------------------
    def _step_once(self) -> None:
        dt = self._dt
        n = self.n
        z = self.rng.standard_normal(n * 13) if self._noisy else None
        wheels = self._command
        if z is not None and self._noise_wheel > 0:
            wheels = wheels * (1.0 + self._noise_wheel * z[: 2 * n].reshape(n, 2))
            np.clip(wheels, -self._max_wheel[:, None], self._max_wheel[:, None], out=wheels)
        self._wheels[:] = wheels
        self._encoders += wheels * dt
        forward, turn = body_velocity(wheels, self._wheel_radius, self._axle)
        old_xy = self._poses[:, :2].copy()
        max_move = float(np.abs(forward).max()) * dt
        substeps = max(1, math.ceil(max_move / (MAX_SUBSTEP_FRACTION * min(self._radius_list))))
        h = dt / substeps
        touched = [False] * n
        for _ in range(substeps):
            self._poses += arc_step(self._poses, forward, turn, h)
            pos = self._poses[:, :2].tolist()
            contact = self.statics.resolve(pos, self._radius_list)
            self._poses[:, :2] = pos
            touched = [a or b for a, b in zip(touched, contact)]
        self._poses[:, 2] = np.remainder(self._poses[:, 2] + math.pi, math.tau) - math.pi
        now = np.array(touched)
        self._collisions += now & ~self._contacts
        self._contacts[:] = now
        # accelerometer: change of the actual (contact-limited) velocity, in the robot frame
        velocity = (self._poses[:, :2] - old_xy) / dt
        acc = (velocity - self._velocity) / dt
        self._velocity[:] = velocity
        c = np.cos(self._poses[:, 2])
        s = np.sin(self._poses[:, 2])
        self._accel[:, 0] = acc[:, 0] * c + acc[:, 1] * s
        self._accel[:, 1] = -acc[:, 0] * s + acc[:, 1] * c
        self._time = (self.step_count + 1) * dt
        self.step_count += 1
        self._sense(z)

    def _sense(self, z: FloatArray | None) -> None:
        """All IR and ground sensors of all robots for the current poses."""
        n = self.n
        x = self._poses[:, 0:1]
        y = self._poses[:, 1:2]
        th = self._poses[:, 2:3]
        c = np.cos(th)
        s = np.sin(th)
        # -- IR: every ray of every robot in one cast ------------------------------------
        self._circle_centres[self._n_static_circles :] = self._poses[:, :2]
        ox = x + c * self._ray_ox - s * self._ray_oy
        oy = y + s * self._ray_ox + c * self._ray_oy
        ang = th + self._ray_angle
        origins = np.stack([ox.ravel(), oy.ravel()], axis=1)
        dirs = np.stack([np.cos(ang).ravel(), np.sin(ang).ravel()], axis=1)
        dist, _ = cast_rays(
            origins,
            dirs,
            self._cast_length,
            self._seg_start,
            self._seg_vector,
            self._circle_centres,
            self._circle_radii,
            self._ray_ignore,
        )
        dist = dist.reshape(n, 8, self._ir_rays)
        nearest = dist.min(axis=2)
        response = (raw_from_distance(dist) * self._ray_weights).sum(axis=2)
        rng_ = self._range[:, None]
        distance = np.minimum(nearest, rng_)
        if z is not None and self._noise_prox > 0:
            zp = z[2 * n : 10 * n].reshape(n, 8)
            sigma = np.hypot(self._noise_prox, relative_sigma(nearest))
            response = response * (1.0 + sigma * zp)
            # a reading that comes back high means "closer": raw ~ 1/d², so d moves by −½
            seen = nearest < rng_
            noisy = np.clip(distance * (1.0 - 0.5 * self._noise_prox * zp), 0.0, rng_)
            distance = np.where(seen, noisy, distance)
        self._prox_distance[:] = distance
        np.clip(response, 0.0, RAW_MAX, out=self._prox_raw)
        # -- ground ---------------------------------------------------------------------------
        gx = x + c * self._ground_lx - s * self._ground_ly
        gy = y + s * self._ground_lx + c * self._ground_ly
        value = self.floor.brightness(np.stack([gx.ravel(), gy.ravel()], axis=1)).reshape(n, 3)
        if z is not None and self._noise_ground > 0:
            value = value + self._noise_ground * z[10 * n : 13 * n].reshape(n, 3)
        np.clip(value, 0.0, 1.0, out=self._ground)
        np.multiply(self._ground, 1023.0, out=self._ground_raw)

    # -- records -------------------------------------------------------------------------------
    def read(self, i: int, sensors: frozenset[Sensor] | Sequence[Sensor]) -> dict[Sensor, Any]:
        """Records of robot ``i``'s ``sensors`` from the latest step.

        The embedded robot has no light sensor model (no light sources in a scene):
        asking for :attr:`Sensor.LIGHT` or the camera here is an error; use
        :meth:`camera` for images.
        """
        out: dict[Sensor, Any] = {}
        for sensor in sensors:
            if sensor is Sensor.PROXIMITY:
                out[sensor] = Proximity(
                    self._prox_distance[i], self._prox_raw[i], float(self._range[i])
                )
            elif sensor is Sensor.GROUND:
                out[sensor] = Ground(self._ground[i], self._ground_raw[i])
            elif sensor is Sensor.POSE:
                px, py, pt = self._poses[i].tolist()
                out[sensor] = Pose(px, py, pt, ground_truth=True)
            elif sensor is Sensor.ENCODERS:
                left, right = self._encoders[i].tolist()
                out[sensor] = WheelEncoders(left, right)
            elif sensor is Sensor.WHEEL_SPEEDS:
                left, right = self._wheels[i].tolist()
                out[sensor] = WheelSpeeds(left, right)
            elif sensor is Sensor.ACCELERATION:
                ax, ay, az = self._accel[i].tolist()
                out[sensor] = Acceleration(ax, ay, az)
            else:
                raise ValueError(
                    f"the embedded simulator has no {Sensor(sensor).value} sensor in read(); "
                    "use camera(i) for images"
                )
        return out

    def camera(self, i: int, size: tuple[int, int] | None = None) -> CameraImage:
        """Robot ``i``'s camera image (``size`` = (width, height), default the scene's)."""
        return CameraImage(self.render_camera(i, size))

    def render_camera(self, i: int, size: tuple[int, int] | None = None) -> npt.NDArray[np.uint8]:
        """The camera pixels (H×W×3 uint8) without wrapping them in a record."""
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
            self._object_colours,
            self._object_heights,
            ignore_circle=self._n_static_circles + i,
        )

    def __repr__(self) -> str:
        return (
            f"<World {self.scene.name!r} robots={list(self.robot_names)} "
            f"t={self._time:.3f}s seed={self.seed}>"
        )
