"""The one point–segment projection (puckboard/geometry.py) the engine and the judge use."""

from __future__ import annotations

import numpy as np
import pytest

from puckboard.geometry import project_on_segment, project_on_segments


def _cases(n: int = 200) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(36)
    w = rng.normal(size=(2, n))
    e = rng.normal(size=(2, n))
    return w[0], w[1], e[0], e[1]


def test_the_closest_point_is_on_the_segment_and_nearest():
    wx, wy, ex, ey = _cases()
    t, qx, qy = project_on_segments(wx, wy, ex, ey, len2=ex * ex + ey * ey)
    assert np.all((t >= 0.0) & (t <= 1.0))
    d = np.hypot(qx, qy)
    # no point of the segment (sampled finely) is nearer than the one found
    s = np.linspace(0.0, 1.0, 401)[:, None]
    sampled = np.hypot(wx - s * ex, wy - s * ey).min(axis=0)
    assert np.all(d <= sampled + 1e-12)
    inside = (t > 0.0) & (t < 1.0)  # there, the offset is perpendicular to the segment
    assert np.allclose((qx * ex + qy * ey)[inside], 0.0, atol=1e-12)


def test_the_ends_clamp():
    assert project_on_segment(-1.0, 0.5, 2.0, 0.0, 4.0) == (0.0, -1.0, 0.5)
    assert project_on_segment(3.0, -0.5, 2.0, 0.0, 4.0) == (1.0, 1.0, -0.5)


def test_floats_and_arrays_give_the_same_bits():
    """The engine's Python loops and its numpy paths must agree to the last bit."""
    wx, wy, ex, ey = _cases()
    len2 = ex * ex + ey * ey
    arrays = project_on_segments(wx, wy, ex, ey, len2=len2)
    for i in range(len(wx)):
        one = project_on_segment(
            float(wx[i]), float(wy[i]), float(ex[i]), float(ey[i]), float(len2[i])
        )
        assert one == (arrays[0][i], arrays[1][i], arrays[2][i])


def test_a_reciprocal_is_multiplied_by_and_a_length_divided_by():
    wx, wy, ex, ey = _cases()
    len2 = ex * ex + ey * ey
    by_length = project_on_segments(wx, wy, ex, ey, len2=len2)[0]
    by_reciprocal = project_on_segments(wx, wy, ex, ey, inv_len2=1.0 / len2)[0]
    assert np.array_equal(by_length, np.clip((wx * ex + wy * ey) / len2, 0.0, 1.0))
    assert np.array_equal(by_reciprocal, np.clip((wx * ex + wy * ey) * (1.0 / len2), 0.0, 1.0))


@pytest.mark.parametrize("given", [{}, {"len2": 1.0, "inv_len2": 1.0}])
def test_one_of_the_two_lengths_is_required(given):
    with pytest.raises(ValueError, match="len2 or inv_len2"):
        project_on_segments(np.ones(2), np.ones(2), np.ones(2), np.ones(2), **given)
