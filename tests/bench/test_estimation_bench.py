"""The estimation benchmark: a short run of its machinery, and its plot."""

from __future__ import annotations

import pytest

from puckboard.bench.estimation.plot import plot_traces
from puckboard.bench.estimation.proximity import measure_proximity
from puckboard.bench.estimation.suite import summarise
from puckboard.bench.estimation.trial import VARIANTS, run_case


def test_short_run_compares_estimates_with_ground_truth():
    info, traces = run_case("line-follow", 0.0, 1, steps=60)
    assert info["cycles"] == 60
    (robot,) = info["robots"]
    assert robot["source_failures"] == 0
    assert set(VARIANTS) <= set(robot)
    # no slip and no contact in the first 3 s: the step counters tell the truth
    assert robot["collisions"] == 0
    assert robot["encoders"]["final_position_error_m"] < 1e-9
    assert robot["encoders"]["distance_m"] > 0.05
    # the miscalibrated filter is off even then
    assert robot["axle +1 mm"]["final_position_error_m"] > 1e-6
    assert len(traces) == len(VARIANTS)
    rows = summarise([info])
    assert {r["variant"] for r in rows} == set(VARIANTS)


def test_wheel_slip_is_invisible_to_the_step_counters():
    info, _ = run_case("line-follow", 0.03, 1, steps=60)
    (robot,) = info["robots"]
    assert robot["collisions"] == 0
    assert robot["encoders"]["final_position_error_m"] > 1e-5


def test_plot_is_written(tmp_path):
    pytest.importorskip("matplotlib")
    _, traces = run_case("line-follow", 0.0, 2, steps=40)
    out = plot_traces(traces[:1], tmp_path / "estimate.png", every=0.5)
    assert out.exists() and out.stat().st_size > 1000


def test_proximity_filter_reduces_the_simulated_sensor_noise_without_bias():
    (row,) = measure_proximity(gaps=(0.02,), steps=200)
    assert row["filtered_sd_m"] < 0.75 * row["raw_sd_m"]
    assert abs(row["filtered_bias_m"]) < 0.5 * row["raw_sd_m"]
