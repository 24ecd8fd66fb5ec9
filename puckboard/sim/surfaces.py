"""The scene's static surfaces, stacked once: every segment and circle a ray can hit.

The IR rays (:mod:`.proximity`), V-REP's cones (:mod:`.cone`) and the camera
(:mod:`.camera`) all ask what lies along a ray, against the same obstacles and walls.
Stacking them once per world, in the order :func:`~.geometry.cast_rays` expects
(segments first, then circles), gives every sensor the same arrays, the IR broad phase
its bounding data, and the camera the colour and height of every object it may draw.
Scenes are 2D; the heights below are the camera's third dimension only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..scenario.scene import CircleObstacle, PolygonObstacle, Scene
from .broadphase import PolygonBound, WallSegment

__all__ = ["OBSTACLE_HEIGHT", "ROBOT_HEIGHT", "WALL_HEIGHT", "Surfaces", "stack_surfaces"]

FloatArray = npt.NDArray[np.float64]

#: Heights (m) used by the camera: scenes are 2D, the camera needs a third dimension.
ROBOT_HEIGHT = 0.05
OBSTACLE_HEIGHT = 0.06
WALL_HEIGHT = 0.08


@dataclass(frozen=True, eq=False)
class Surfaces:
    """What rays can hit, in :func:`~.geometry.cast_rays` order: segments, then circles."""

    #: S×2 start points and edge vectors: every polygon's edges, then the arena's 4 walls
    seg_start: FloatArray
    seg_vector: FloatArray
    #: (x, y, radius) of each circular obstacle
    static_circles: list[tuple[float, float, float]]
    #: the IR broad phase's bounds: a bounding circle per polygon and its edges' indices
    polygons: list[PolygonBound]
    #: the arena's walls, each tested exactly by the broad phase
    walls: list[WallSegment]
    #: (C + N)×2 circle centres: the C static circles, then one per robot, which the
    #: camera moves to the robots' positions before it renders
    circle_centres: FloatArray
    circle_radii: FloatArray
    #: colour (K×3) and height (K, m) of every segment and circle, for the camera
    object_colours: npt.NDArray[np.uint8]
    object_heights: FloatArray
    #: IR reflectance of each static circle and of each segment (walls: 1), for the IR
    #: rays (:mod:`.reflectance`)
    circle_reflectance: tuple[float, ...] = ()
    seg_reflectance: tuple[float, ...] = ()

    @property
    def n_static_circles(self) -> int:
        return len(self.static_circles)


def stack_surfaces(scene: Scene, body_radii: FloatArray) -> Surfaces:
    """Stack ``scene``'s obstacles and walls, and a circle per robot of ``body_radii``."""
    starts: list[FloatArray] = []
    vectors: list[FloatArray] = []
    seg_colours: list[tuple[int, int, int]] = []
    seg_heights: list[float] = []
    circles: list[tuple[float, float, float]] = []
    circle_colours: list[tuple[int, int, int]] = []
    seg_reflectance: list[float] = []
    circle_reflectance: list[float] = []
    for ob in scene.obstacles:
        if isinstance(ob, PolygonObstacle):
            a, e = ob.edges()
            starts.append(a)
            vectors.append(e)
            seg_colours += [ob.colour] * len(a)
            seg_heights += [OBSTACLE_HEIGHT] * len(a)
            seg_reflectance += [ob.ir_reflectance] * len(a)
        elif isinstance(ob, CircleObstacle):
            circles.append((ob.x, ob.y, ob.radius))
            circle_colours.append(ob.colour)
            circle_reflectance.append(ob.ir_reflectance)
    if scene.arena is not None:
        ar = scene.arena
        a, e = ar.edges()
        starts.append(a)
        vectors.append(e)
        seg_colours += [ar.colour] * 4
        seg_heights += [WALL_HEIGHT] * 4
        seg_reflectance += [1.0] * 4
    polygons, walls = _bounds(scene, starts, vectors)
    n_robots = len(body_radii)
    n_static = len(circles)
    circle_centres = np.zeros((n_static + n_robots, 2))
    if circles:
        circle_centres[:n_static] = np.array(circles)[:, :2]
    robot_colours = [r.colour for r in scene.robots]
    return Surfaces(
        seg_start=np.vstack(starts) if starts else np.zeros((0, 2)),
        seg_vector=np.vstack(vectors) if vectors else np.zeros((0, 2)),
        static_circles=[(float(c[0]), float(c[1]), float(c[2])) for c in circles],
        polygons=polygons,
        walls=walls,
        circle_centres=circle_centres,
        circle_radii=np.concatenate([np.array([c[2] for c in circles], dtype=float), body_radii]),
        object_colours=np.array(
            seg_colours + circle_colours + robot_colours, dtype=np.uint8
        ).reshape(-1, 3),
        object_heights=np.array(
            seg_heights + [OBSTACLE_HEIGHT] * n_static + [ROBOT_HEIGHT] * n_robots, dtype=float
        ),
        circle_reflectance=tuple(circle_reflectance),
        seg_reflectance=tuple(seg_reflectance),
    )


def _bounds(
    scene: Scene, starts: list[FloatArray], vectors: list[FloatArray]
) -> tuple[list[PolygonBound], list[WallSegment]]:
    """Bounding data for the IR broad phase: polygons (bounding circle and their edges'
    indices) and walls (each wall segment tested exactly)."""
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
    return polygons, walls
