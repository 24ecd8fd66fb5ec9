"""The closest point of a segment to a point: plane geometry the engine and the judge share.

A robot pushed out of a polygon, the proximity sensors' broad phase, the ground sensors'
distance to the line and the judge's position along the track and distance to an
obstacle all ask the same question: where on the segment from ``a`` to ``a + e`` is the
point closest to ``p``? With ``w = p - a``, the answer is ``a + t e`` for
``t = clamp((w · e) / |e|², 0, 1)``, and the point's offset from it is ``w - t e``.

It is written here once, on the ground floor (this module imports nothing of puckboard),
so the judge in :mod:`puckboard.scenario`, which sits below the engine and never imports
it, and :mod:`puckboard.sim` share it. Two forms, the same arithmetic in the same order:

* :func:`project_on_segment` for plain Python floats, where the engine loops over a few
  segments per robot and a numpy call would cost more than the arithmetic;
* :func:`project_on_segments` for numpy arrays (any shapes that broadcast).

Callers that divide by ``|e|²`` many times pass its reciprocal (``inv_len2``) instead;
that is a different rounding from dividing (``x * (1/y)`` is not always ``x / y``), so
both spellings are kept, each where it has always been used, and results stay the same
to the last bit.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

__all__ = ["project_on_segment", "project_on_segments"]

FloatArray = npt.NDArray[np.float64]


def project_on_segment(
    wx: float, wy: float, ex: float, ey: float, len2: float
) -> tuple[float, float, float]:
    """``(t, qx, qy)`` for one segment, in plain floats: ``(wx, wy)`` is the point
    relative to the segment's start, ``(ex, ey)`` the segment, ``len2`` its squared
    length (> 0); ``t`` in [0, 1] locates the closest point, ``(qx, qy)`` is the point's
    offset from it."""
    t = (wx * ex + wy * ey) / len2
    t = 0.0 if t < 0.0 else 1.0 if t > 1.0 else t
    return t, wx - t * ex, wy - t * ey


def project_on_segments(
    wx: FloatArray,
    wy: FloatArray,
    ex: FloatArray,
    ey: FloatArray,
    *,
    len2: FloatArray | float | None = None,
    inv_len2: FloatArray | float | None = None,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``(t, qx, qy)`` as :func:`project_on_segment`, element by element for arrays that
    broadcast together. Give the squared lengths (``len2``, divided by) or their
    reciprocals (``inv_len2``, multiplied by), not both."""
    if (len2 is None) == (inv_len2 is None):
        raise ValueError("give len2 or inv_len2, not both and not neither")
    t = wx * ex
    t += wy * ey
    if len2 is not None:
        t /= len2
    elif inv_len2 is not None:
        t *= inv_len2
    np.maximum(t, 0.0, out=t)  # two ufuncs: cheaper than np.clip's wrapper, same values
    np.minimum(t, 1.0, out=t)
    return t, wx - t * ex, wy - t * ey
