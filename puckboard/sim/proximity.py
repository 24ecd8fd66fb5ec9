"""The IR proximity sensors of every robot in a world, computed together once per step.

Each sensor casts ``rays`` rays spread over its aperture (see docs/simulator.md for why).
Casting them one by one from Python would cost tens of microseconds each, so all rays of
all robots are tested against the objects near them in one set of numpy calls per step
(:func:`~puckboard.sim.geometry.segment_hits`, :func:`~puckboard.sim.geometry.circle_hits`),
and only when something is near: a conservative broad phase
(:class:`~.broadphase.SensorBroadPhase`, the same the cone sensors of :mod:`.cone` use
with their own reach) finds which robots can see anything and, for each of them, which
circles and segments it may see. Most steps of a line-following run cast no ray at all.

Each robot's rays are tested against *its own* candidates only, one row per (robot,
candidate) pair, not against every object near anyone: with 50 robots that is a few
objects per ray instead of thirty, and the cost per robot stays flat. For a few robots
the broad phase answers in plain Python and the arrays each outcome selects are cached
(outcomes change every few dozen steps); for more it answers in arrays, and the cast is
built from them each step.

Per sensor the model computes what its photodiode reads: the Gaussian-weighted mean of
the rays' responses through the Webots table (:mod:`puckboard.ir_response`), times the
sensor's gain, with relative noise. What the robot makes of it (the firmware's
calibration, the distance) is :mod:`.ir_calibration`'s.

Every hit is computed with the same arithmetic for each (ray, object) pair whatever else
is cast with it, and a ray's nearest hit is a minimum, which does not depend on the order
or the number of candidates: so the readings do not depend on how the broad phase groups
the work (tests/sim/test_sim_broadphase.py compares the two broad phases).
"""

from __future__ import annotations

import cmath
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..ir_response import _D, _RAW, _SIGMA, TABLE_RANGE, raw_from_distance, relative_sigma
from ..profile import RobotProfile
from .broadphase import PolygonBound, SensorBroadPhase, WallSegment
from .geometry import circle_hits, segment_hits
from .reflectance import reflectances, reflected, row_reflectance

__all__ = ["ProximitySensors"]

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class _Cast:
    """The rays to cast and the objects each robot may see, for one broad-phase outcome.

    ``k`` robots cast (``robots``, in increasing order), ``8·rays`` rays each. Every
    (robot, candidate object) pair is one row: the object's data as P×1 columns, the
    robot's rays gathered into that row, so each hit is tested once per ray of the robot
    that may see the object and never for a robot that cannot (no padding to the longest
    list: at 50 robots a quarter of the work of a padded layout). ``order`` groups the rows
    of circles and segments by robot and ``starts`` says where each robot's rows begin, so
    the nearest hit of every ray is one ``minimum.reduceat`` over the rows.
    """

    robots: npt.NDArray[np.intp]
    robot_list: tuple[int, ...]
    local_origin: npt.NDArray[np.complex128]
    local_direction: npt.NDArray[np.complex128]
    circle_rows: npt.NDArray[np.intp] | None  # which cast robot (0..k-1) each circle row is
    circle_index: npt.NDArray[np.intp]  # which circle (static ones first, then robots)
    circle_radii_sq: FloatArray  # P×1
    seg_rows: npt.NDArray[np.intp] | None
    seg_ax: FloatArray  # P×1 each
    seg_ay: FloatArray
    seg_ex: FloatArray
    seg_ey: FloatArray
    order: npt.NDArray[np.intp] | None  # None: the rows are already grouped by robot
    starts: npt.NDArray[np.intp] | None  # None: one row per robot
    weights: FloatArray
    range_col: FloatArray
    every_robot: bool
    reflect: FloatArray | None  # each row's obstacle IR reflectance (None: all 1)


class ProximitySensors:
    """IR sensor layout of N robots and the static things their rays can hit.

    ``robots`` (world indices) are those that sense with rays; the others (V-REP's cone
    model, :mod:`.cone`) read what their own sensors give, and this class only keeps their
    rows of the N×8 arrays. ``seg_start``/``seg_vector`` are every static segment (polygon
    edges, walls); circles are the static round obstacles followed by one circle per robot
    (their centres are the poses passed to :meth:`sense` each step). ``polygons`` and
    ``walls`` say which segments belong to what, for the broad phase.
    ``circle_reflectance`` (one per static circle) and ``seg_reflectance`` (one per
    segment) are the objects' IR reflectance (:mod:`.reflectance`); None: every one 1.
    """

    def __init__(
        self,
        profiles: Sequence[RobotProfile],
        *,
        robots: Sequence[int],
        rays: int,
        seg_start: FloatArray,
        seg_vector: FloatArray,
        static_circles: Sequence[tuple[float, float, float]],
        polygons: Sequence[PolygonBound],
        walls: Sequence[WallSegment],
        circle_reflectance: Sequence[float] | None = None,
        seg_reflectance: Sequence[float] | None = None,
    ) -> None:
        if rays < 1:
            raise ValueError(f"ir_rays must be at least 1, got {rays}")
        n = len(profiles)
        self.n = n
        self.rays = rays
        self.seg_start = seg_start
        self.seg_vector = seg_vector
        self.static_circles = tuple(static_circles)
        self.n_static = len(static_circles)
        #: the robots that cast rays (increasing world indices)
        self.robots = tuple(sorted(robots))
        self.any_rays = bool(self.robots)
        self.robot_radii = [p.body_radius for p in profiles]
        self.circle_radii = np.array([c[2] for c in static_circles] + self.robot_radii, dtype=float)
        # robots' bodies reflect as the table's surface; None where every object does
        self._circle_reflect = reflectances(circle_reflectance, robots=n)
        self._seg_reflect = reflectances(seg_reflectance)
        self.range = np.array([p.prox_range for p in profiles])[:, None]  # N×1
        self._far_nearest = np.repeat(self.range, 8, axis=1)  # what nothing seen reads
        self.cast_length = max(TABLE_RANGE, float(self.range.max()))

        origin_x = np.zeros((n, 8 * rays))
        origin_y = np.zeros((n, 8 * rays))
        angle = np.zeros((n, 8 * rays))
        weights = np.zeros((n, 8, rays))
        for i, p in enumerate(profiles):
            if len(p.prox_poses) != 8:
                raise ValueError(f"profile {p.name!r} must have 8 proximity sensor poses")
            half = p.prox_aperture / 2
            offsets = np.linspace(-half, half, rays) if rays > 1 else np.zeros(1)
            # Webots combines a sensor's rays with Gaussian weights; σ = aperture/4 puts
            # the outermost rays at two standard deviations. Each sensor's gain scales
            # its weights: the response costs no multiplication more per step.
            sigma = max(p.prox_aperture / 4.0, 1e-9)
            w = np.exp(-0.5 * (offsets / sigma) ** 2)
            for s, pose in enumerate(p.prox_poses):
                cols = slice(s * rays, (s + 1) * rays)
                origin_x[i, cols] = pose.x
                origin_y[i, cols] = pose.y
                angle[i, cols] = pose.heading + offsets
                weights[i, s] = w / w.sum() * p.ir_gain[s]
        self._local_origin = origin_x + 1j * origin_y
        self._local_direction = np.exp(1j * angle)
        self._weights = weights
        #: what a sensor reads when its rays hit nothing: its gain times the table's far
        #: baseline (summed as a response is, so a free sensor reads exactly this)
        self.baseline_raw = (raw_from_distance(np.inf) * weights).sum(axis=2)
        # how far from a robot's centre its rays can reach
        offset = max(math.hypot(q.x, q.y) for p in profiles for q in p.prox_poses)
        self.reach = offset + self.cast_length
        #: which objects each casting robot may see within the rays' reach
        self.broad_phase = SensorBroadPhase(
            self.robots,
            [self.reach] * len(self.robots),
            self.robot_radii,
            static_circles=static_circles,
            polygons=polygons,
            walls=walls,
            n_segments=int(seg_start.shape[0]),
        )
        self._cache: dict[tuple[tuple[int, tuple[int, ...], tuple[int, ...]], ...], _Cast] = {}
        self._far_sigma_noise = math.nan
        self._far_sigma_value = self._far_nearest
        self._build_vector_tables()

    def _build_vector_tables(self) -> None:
        """Every object's data as arrays, built once.

        Circles are the static ones, then the robots (their centres written each step).
        """
        n, n_static = self.n, self.n_static
        self._centres = np.zeros((n_static + n, 2))
        if n_static:
            self._centres[:n_static] = np.array([c[:2] for c in self.static_circles])
        radii = self.circle_radii
        self._radii_sq = radii * radii
        self._n_segments = int(self.seg_start.shape[0])
        # one row per segment (ax, ay, ex, ey): a candidate list gathers all four at once
        self._segments = np.hstack([self.seg_start, self.seg_vector]).reshape(-1, 4)

    # -- the cast of one broad-phase outcome -------------------------------------------
    def _cast_python(self, poses: Sequence[Sequence[float]]) -> _Cast | None:
        """The cast for this step from the Python broad phase (None: nobody casts).

        Which robots are near which objects changes only every few dozen steps, so the
        arrays of each outcome are built once and cached.
        """
        robots, circles_of, segments_of = self.broad_phase.lists(poses)
        if not robots:
            return None
        key = tuple((i, tuple(circles_of[i]), tuple(segments_of[i])) for i in robots)
        cast = self._cache.get(key)
        if cast is None:
            circle_rows = [col for col, i in enumerate(robots) for _ in circles_of[i]]
            circle_index = [c for i in robots for c in circles_of[i]]
            seg_rows = [col for col, i in enumerate(robots) for _ in segments_of[i]]
            seg_index = [k for i in robots for k in segments_of[i]]
            cast = self._make_cast(
                np.array(robots, dtype=np.intp),
                np.array(circle_rows, dtype=np.intp),
                np.array(circle_index, dtype=np.intp),
                np.array(seg_rows, dtype=np.intp),
                np.array(seg_index, dtype=np.intp),
            )
            if len(self._cache) > 1024:
                self._cache.clear()
            self._cache[key] = cast
        return cast

    def _cast_numpy(self, xy: FloatArray) -> _Cast | None:
        """The cast for this step from the vectorised broad phase (None: nobody casts)."""
        robots, circle_rows, circle_index, seg_hit = self.broad_phase.arrays(xy)
        if robots.shape[0] == 0:
            return None
        seg_rows, seg_index = np.nonzero(seg_hit)
        return self._make_cast(robots, circle_rows, circle_index, seg_rows, seg_index)

    def _make_cast(
        self,
        robots: npt.NDArray[np.intp],
        circle_rows: npt.NDArray[np.intp],
        circle_index: npt.NDArray[np.intp],
        seg_rows: npt.NDArray[np.intp],
        seg_index: npt.NDArray[np.intp],
    ) -> _Cast:
        """The arrays of one cast: the rays of ``robots`` (k of them) and the candidate
        pairs, circle ``circle_index[p]`` for cast robot ``circle_rows[p]`` (0..k-1) and
        the same for segments."""
        k = robots.shape[0]
        rows = np.concatenate([circle_rows, seg_rows])
        order: npt.NDArray[np.intp] | None = np.argsort(rows, kind="stable")
        grouped = rows[order]
        if np.array_equal(grouped, rows):
            order = None  # already grouped by robot (one kind, or circles then segments)
        starts = None
        if rows.shape[0] != k:  # some robot has several candidates
            counts = np.bincount(grouped, minlength=k)
            starts = np.cumsum(counts) - counts
        segments = self._segments[seg_index]
        every = k == self.n
        return _Cast(
            robots=robots,
            robot_list=tuple(robots.tolist()),
            local_origin=self._local_origin if every else self._local_origin[robots],
            local_direction=self._local_direction if every else self._local_direction[robots],
            circle_rows=circle_rows if circle_rows.shape[0] else None,
            circle_index=circle_index,
            circle_radii_sq=self._radii_sq[circle_index][:, None],
            seg_rows=seg_rows if seg_rows.shape[0] else None,
            seg_ax=segments[:, 0:1],
            seg_ay=segments[:, 1:2],
            seg_ex=segments[:, 2:3],
            seg_ey=segments[:, 3:4],
            order=order,
            starts=starts,
            weights=self._weights if every else self._weights[robots],
            range_col=self.range if every else self.range[robots],
            every_robot=every,
            reflect=row_reflectance(
                self._circle_reflect, self._seg_reflect, circle_index, seg_index, order
            ),
        )

    # -- the step --------------------------------------------------------------------------
    def sense(
        self,
        poses: Sequence[Sequence[float]],
        raw: FloatArray,
        *,
        noise: float = 0.0,
        z: FloatArray | None = None,
    ) -> bool:
        """Fill ``raw`` (N×8) with each sensor's response for robots at ``poses`` (x, y, θ);
        False, and ``raw`` left as it is, when nobody is near anything.

        The robots' bodies are circles at ``poses``. A response is ``gain · Σ w·T(d)`` over
        the sensor's rays, on the table's scale (the ambient baseline ≈67 included: what
        the photodiode reads before the firmware subtracts its calibration). With
        ``noise`` > 0, ``z`` (N×8 standard normals) multiplies it by ``1 + σ·z``, σ =
        √(noise² + σ_table²) at the nearest hit (the range if nothing is seen). When
        nobody casts (most steps of a line-following run) every response is
        :attr:`baseline_raw` times ``1 +`` :meth:`far_noise`, and the table look-ups
        would decide nothing: the caller takes it from there.
        """
        if not self.any_rays:
            return False  # every robot senses with V-REP's cones (:mod:`.cone`)
        cast, frames = self._broad_phase(poses)
        if cast is None:
            return False
        nearest = self._respond(cast, frames, raw, noise > 0 and z is not None)
        if noise > 0 and z is not None:
            # the table's own σ at the nearest hit (the range if nothing is seen)
            sigma = np.hypot(noise, np.interp(nearest, _D, _SIGMA))  # relative_sigma
            sigma *= z
            sigma += 1.0
            raw *= sigma
        return True

    def far_noise(self, noise: float, z: FloatArray | None) -> FloatArray | None:
        """σ·z of sensors that see nothing (they read the range: σ is fixed), or None
        without noise."""
        if noise <= 0 or z is None:
            return None
        if noise != self._far_sigma_noise:
            self._far_sigma_value = np.hypot(noise, relative_sigma(self._far_nearest))
            self._far_sigma_noise = noise
        return self._far_sigma_value * z

    def response(self, poses: Sequence[Sequence[float]]) -> FloatArray:
        """Every sensor's noise-free response at ``poses`` (N×8, as :meth:`sense` fills
        ``raw``), in a new array: what a calibration averages its many samples to."""
        raw = np.empty((self.n, 8))
        cast, frames = self._broad_phase(poses) if self.any_rays else (None, None)
        if cast is None:
            raw[:] = self.baseline_raw
        else:
            self._respond(cast, frames, raw, False)
        return raw

    def _broad_phase(
        self, poses: Sequence[Sequence[float]]
    ) -> tuple[_Cast | None, npt.NDArray[np.complex128] | None]:
        """This step's cast and each casting robot's (position, rotation) as complex numbers."""
        n_static = self.n_static
        frames = None
        if self.broad_phase.in_python():
            cast = self._cast_python(poses)
            if cast is not None:
                if cast.circle_rows is not None:
                    for i in range(self.n):
                        self._centres[n_static + i] = poses[i][:2]
                frames = np.array(
                    [
                        (complex(poses[i][0], poses[i][1]), cmath.exp(1j * poses[i][2]))
                        for i in cast.robot_list
                    ]
                )
        else:
            pose_array = np.array(poses)
            cast = self._cast_numpy(pose_array[:, :2])
            self._centres[n_static : n_static + self.n] = pose_array[:, :2]
            if cast is not None:
                # the same values as the loop above: numpy's complex exp and cmath's
                # both take libm's cos and sin (checked on two million angles)
                cast_poses = pose_array[cast.robots]
                frames = np.empty((cast_poses.shape[0], 2), dtype=complex)
                frames[:, 0].real = cast_poses[:, 0]
                frames[:, 0].imag = cast_poses[:, 1]
                frames[:, 1] = np.exp(1j * cast_poses[:, 2])
        return cast, frames

    def _respond(
        self,
        cast: _Cast,
        frames: npt.NDArray[np.complex128] | None,
        raw: FloatArray,
        want_nearest: bool,
    ) -> FloatArray:
        """Cast the rays of ``cast`` and write every robot's response into ``raw``; with
        ``want_nearest``, also return each sensor's nearest hit capped at the range (N×8)."""
        # rays as complex numbers: origin = position + rotation·local, direction =
        # rotation·local direction (fewer numpy calls than separate x and y)
        assert frames is not None
        position = frames[:, 0:1]
        rotation = frames[:, 1:2]
        origin = position + rotation * cast.local_origin  # k robots × 8·rays
        direction = rotation * cast.local_direction
        # one row per (robot, candidate object): that robot's rays against it
        hits = []
        if cast.circle_rows is not None:
            o, d = origin[cast.circle_rows], direction[cast.circle_rows]
            c, r2 = self._centres[cast.circle_index], cast.circle_radii_sq
            hits.append(circle_hits(o.real, o.imag, d.real, d.imag, c[:, 0:1], c[:, 1:2], r2))
        if cast.seg_rows is not None:
            o, d = origin[cast.seg_rows], direction[cast.seg_rows]
            ends = (cast.seg_ax, cast.seg_ay, cast.seg_ex, cast.seg_ey)
            hits.append(segment_hits(o.real, o.imag, d.real, d.imag, *ends))
        # the nearest hit of each ray over its robot's rows
        allt = hits[0] if len(hits) == 1 else np.concatenate(hits, axis=0)
        if cast.order is not None:
            allt = allt[cast.order]
        nearest = allt if cast.starts is None else np.minimum.reduceat(allt, cast.starts, axis=0)
        dist = nearest.reshape(len(cast.robot_list), 8, self.rays)
        # Hits beyond the table need no masking: it keeps its last value beyond
        # TABLE_RANGE (as for ``inf``), and the nearest hit is capped at the range.
        # The weights carry each sensor's gain.
        response = np.interp(dist, _D, _RAW)
        if cast.reflect is not None:
            response = reflected(response, allt, nearest, cast.reflect, cast.starts)
        if cast.every_robot:
            np.multiply(response, cast.weights).sum(axis=2, out=raw)
            if want_nearest:
                return np.minimum(dist.min(axis=2), self.range)
            return self._far_nearest
        # the robots that cast no ray see nothing this step
        raw[:] = self.baseline_raw
        raw[cast.robots] = (response * cast.weights).sum(axis=2)
        if not want_nearest:
            return self._far_nearest
        near = self._far_nearest.copy()
        near[cast.robots] = np.minimum(dist.min(axis=2), cast.range_col)
        return near
