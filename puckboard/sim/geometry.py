"""Vectorised 2D geometry: ray casting against circles and segments, point–polyline distance.

Both the IR sensors and the camera are rays; casting them one by one from Python costs
tens of microseconds each, while numpy's cost is per *call*, not per element (a 16-ray
and a 96-ray cast differ by less than 2×). So all rays are tested against every circle
(round obstacles, robots) and every segment (polygon edges, arena walls) at once: the
camera through :func:`cast_rays`, the IR sensors through its two kernels,
:func:`segment_hits` and :func:`circle_hits`, laid out objects-first.

All functions take plain arrays (SI metres) and allocate only their results.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

__all__ = [
    "cast_rays",
    "circle_hits",
    "ray_hits",
    "segment_hits",
]

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.intp]


def cast_rays(
    origins: FloatArray,
    directions: FloatArray,
    max_length: float,
    seg_start: FloatArray,
    seg_vector: FloatArray,
    circle_centres: FloatArray,
    circle_radii: FloatArray,
    ignore: npt.NDArray[np.bool_] | None = None,
) -> tuple[FloatArray, IntArray]:
    """Distance along each ray to the first surface hit, and which object it hit.

    ``origins`` and ``directions`` (unit vectors) are R×2. Segments run from
    ``seg_start`` to ``seg_start + seg_vector`` (S×2 each); circles are C×2 centres with
    C radii. ``ignore`` (R×C, optional) masks circles a ray must not see (a robot's own
    body, on or inside which its sensors sit).

    Returns ``(distance, hit)``: distance is ``inf`` where nothing lies within
    ``max_length``; ``hit`` indexes segments as ``0..S-1`` and circles as ``S..S+C-1``
    (``-1`` for no hit). A ray starting inside a circle reports distance 0.
    """
    n_rays = origins.shape[0]
    allt = ray_hits(
        origins[:, 0:1],
        origins[:, 1:2],
        directions[:, 0:1],
        directions[:, 1:2],
        seg_start,
        seg_vector,
        circle_centres,
        circle_radii,
        ignore,
    )
    if allt is None:
        return np.full(n_rays, np.inf), np.full(n_rays, -1, dtype=np.intp)
    hit = allt.argmin(axis=1)
    dist = allt[np.arange(n_rays), hit]
    far = dist > max_length
    dist[far] = np.inf
    hit[far] = -1
    return dist, hit


def ray_hits(
    ox: FloatArray,
    oy: FloatArray,
    dx: FloatArray,
    dy: FloatArray,
    seg_start: FloatArray,
    seg_vector: FloatArray,
    circle_centres: FloatArray,
    circle_radii: FloatArray,
    ignore: npt.NDArray[np.bool_] | None = None,
) -> FloatArray | None:
    """The distance along each ray to every object (R×(S+C), ``inf`` where it misses).

    The kernel behind :func:`cast_rays`, for callers that only need the nearest
    distance (``.min(axis=1)``) and already hold the rays as R×1 coordinate columns.
    Returns None when there is nothing to hit.
    """
    n_seg = seg_start.shape[0]
    n_circ = circle_centres.shape[0]
    candidates: list[FloatArray] = []
    if n_seg:
        candidates.append(
            segment_hits(
                ox, oy, dx, dy, seg_start[:, 0], seg_start[:, 1], seg_vector[:, 0], seg_vector[:, 1]
            )
        )
    if n_circ:
        visible = None if ignore is None else ~ignore
        candidates.append(
            circle_hits(
                ox,
                oy,
                dx,
                dy,
                circle_centres[:, 0],
                circle_centres[:, 1],
                circle_radii * circle_radii,
                visible,
            )
        )
    if not candidates:
        return None
    return candidates[0] if len(candidates) == 1 else np.concatenate(candidates, axis=1)


def segment_hits(
    ox: FloatArray,
    oy: FloatArray,
    dx: FloatArray,
    dy: FloatArray,
    ax: FloatArray,
    ay: FloatArray,
    ex: FloatArray,
    ey: FloatArray,
) -> FloatArray:
    """Distance along rays to segments from (ax, ay) to (ax + ex, ay + ey), ``inf`` on a miss.

    Every argument is an array and the result has their broadcast shape: rays as R×1
    columns and segments as length-S rows give R×S (what :func:`ray_hits` does), rays
    as length-R rows and segments as S×1 columns give S×R.
    """
    with np.errstate(divide="ignore", invalid="ignore"):  # parallel rays: 0/0
        wx = ax - ox
        wy = ay - oy
        den = dx * ey - dy * ex
        t = (wx * ey - wy * ex) / den
        u = (wx * dy - wy * dx) / den
        ok = (t >= 0.0) & (u >= 0.0) & (u <= 1.0)
        return np.where(ok, t, np.inf)


def circle_hits(
    ox: FloatArray,
    oy: FloatArray,
    dx: FloatArray,
    dy: FloatArray,
    cx: FloatArray,
    cy: FloatArray,
    radii_sq: FloatArray,
    visible: npt.NDArray[np.bool_] | None = None,
) -> FloatArray:
    """Distance along rays to circles centred at (cx, cy), ``inf`` on a miss; 0 from inside.

    Shapes broadcast as in :func:`segment_hits`; ``radii_sq`` holds the squared radii and
    ``visible`` (optional, the result's shape) masks out pairs a ray must not see.
    """
    fx = ox - cx
    fy = oy - cy
    b = fx * dx + fy * dy
    c = fx * fx + fy * fy - radii_sq
    disc = b * b - c
    ok = disc >= 0.0
    # the root only where the ray meets the circle (no invalid-value warning to
    # suppress; the other entries are masked out below)
    root = np.sqrt(disc, out=disc, where=ok)
    t = np.subtract(-b, root, out=root)
    # inside the circle (c < 0): the surface is at distance 0 from the ray's start
    t[c < 0.0] = 0.0
    ok &= t >= 0.0
    if visible is not None:
        ok &= visible
    return np.where(ok, t, np.inf)
