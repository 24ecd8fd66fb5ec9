"""Obstacles that send back less IR than the surface the response curve was measured on.

The e-puck's IR proximity sensors measure reflected infrared, so what they see depends
on the object's surface as much as on its distance: black objects are hardly detected
(epucklib's documentation, http://jianingchen.github.io/epucklib/html/a00048.html).
The response table (:mod:`puckboard.ir_response`) is one surface's; an obstacle's
``ir_reflectance`` ρ scales the light it returns above the ambient baseline, so a ray
whose nearest hit is that obstacle reads ``T∞ + ρ·(T(d) − T∞)``: ρ = 1 is the table,
ρ = 0 an object the sensor cannot see at all (it still blocks the rays behind it).

Only scenes with an obstacle of ρ ≠ 1 pay for this: :func:`row_reflectance` returns
None otherwise, and the IR model (:mod:`.proximity`) then computes exactly what it
computed before reflectance existed.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from ..ir_response import FAR_RAW

__all__ = ["reflectances", "reflected", "row_reflectance"]

FloatArray = npt.NDArray[np.float64]


def reflectances(values: Sequence[float] | None, robots: int = 0) -> FloatArray | None:
    """``values`` as an array, followed by ``robots`` ones (the robots' bodies reflect as
    the table's surface); None when every value is 1, so nothing needs scaling."""
    if values is None or all(v == 1.0 for v in values):
        return None
    return np.concatenate([np.asarray(values, dtype=float), np.ones(robots)])


def row_reflectance(
    circle_reflectance: FloatArray | None,
    seg_reflectance: FloatArray | None,
    circle_index: npt.NDArray[np.intp],
    seg_index: npt.NDArray[np.intp],
    order: npt.NDArray[np.intp] | None,
) -> FloatArray | None:
    """Each candidate row's reflectance (P×1, rows in cast order: circles, then
    segments, then regrouped by ``order``), or None when every object has ρ = 1."""
    if circle_reflectance is None and seg_reflectance is None:
        return None
    circles = (
        np.ones(circle_index.shape[0])
        if circle_reflectance is None
        else circle_reflectance[circle_index]
    )
    segments = (
        np.ones(seg_index.shape[0]) if seg_reflectance is None else seg_reflectance[seg_index]
    )
    rows = np.concatenate([circles, segments])
    if order is not None:
        rows = rows[order]
    return rows[:, None]


def reflected(
    response: FloatArray,
    hits: FloatArray,
    nearest: FloatArray,
    reflectance: FloatArray,
    starts: npt.NDArray[np.intp] | None,
) -> FloatArray:
    """``response`` (the table's value at each ray's nearest hit, any shape with the
    rays' count) with each ray's light scaled by the reflectance of what it hit.

    ``hits`` (P×R) is every candidate row's hit distance per ray, grouped by robot,
    ``starts`` where each robot's rows begin (None: one row each), ``nearest`` (k×R)
    the minimum over each robot's rows. A ray that hits nothing reads ``T∞`` whatever
    the reflectance, as it must.
    """
    if starts is None:
        rho = np.broadcast_to(reflectance, hits.shape)
    else:
        counts = np.diff(np.append(starts, hits.shape[0]))
        nearest_of_row = np.repeat(nearest, counts, axis=0)
        candidates = np.where(hits <= nearest_of_row, reflectance, np.inf)
        rho = np.minimum.reduceat(candidates, starts, axis=0)
    rho = rho.reshape(response.shape)
    return FAR_RAW + rho * (response - FAR_RAW)
