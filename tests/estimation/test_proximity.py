"""The per-sensor IR distance filter."""

from __future__ import annotations

import numpy as np
import pytest

from puckboard.estimation import ProximityFilter
from puckboard.records import Proximity

DT = 0.05


def test_reduces_variance_of_a_noisy_constant():
    rng = np.random.default_rng(7)
    truth = np.array([0.01, 0.02, 0.03, 0.04, 0.045, 0.015, 0.025, 0.035])
    sigma = 0.002
    f = ProximityFilter(sigma=sigma)
    raw, out = [], []
    for _ in range(400):
        z = np.clip(truth + rng.normal(0.0, sigma, 8), 0.0, 0.0499)
        raw.append(z)
        out.append(f.update(z, DT))
    raw_err = np.array(raw[100:]) - truth
    out_err = np.array(out[100:]) - truth
    assert np.all(out_err.var(axis=0) < raw_err.var(axis=0) / 2)
    assert np.all(np.abs(out_err.mean(axis=0)) < 0.5 * sigma)  # no bias
    assert np.all(f.variance < sigma**2)  # and the filter knows it is better than one reading


def test_tracks_an_approaching_wall_without_lag():
    f = ProximityFilter(n=1)
    speed = -0.03  # m/s: the robot creeps towards a wall
    d = 0.048
    errors = []
    for _ in range(30):
        out = f.update([d], DT)
        errors.append(out[0] - d)
        d += speed * DT
    assert abs(errors[-1]) < 1e-4  # constant velocity is the model: no steady-state lag


def test_nothing_in_range_reads_the_range_and_a_new_object_restarts_the_track():
    f = ProximityFilter(n=2, range=0.05)
    for _ in range(20):
        f.update([0.04, 0.05], DT)
    out = f.update([0.04, 0.05], DT)
    assert out[1] == 0.05 and f.variance[1] == 0.0 and not f.active[1]
    assert out[0] == pytest.approx(0.04)
    jumped = f.update([0.01, 0.05], DT)  # a post appears much closer: not glided towards
    assert jumped[0] == pytest.approx(0.01)
    f.update([0.05, 0.05], DT)
    assert f.update([0.03, 0.05], DT)[0] == pytest.approx(0.03)  # fresh track after a gap


def test_filter_record_keeps_the_record_type_and_raw_values():
    f = ProximityFilter()
    prox = Proximity(np.full(8, 0.03), np.full(8, 250.0), 0.05)
    out = f.filter_record(prox, DT)
    assert isinstance(out, Proximity)
    np.testing.assert_array_equal(out.raw, prox.raw)
    np.testing.assert_allclose(out.distance, 0.03)


def test_bad_input_is_refused():
    with pytest.raises(ValueError, match="sigma"):
        ProximityFilter(sigma=0.0)
    with pytest.raises(ValueError, match="8 distances"):
        ProximityFilter().update([0.01, 0.02], DT)
