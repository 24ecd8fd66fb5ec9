"""The robustness radius, on counts worked out by hand."""

from __future__ import annotations

import pytest

from puckboard.sweep.stats import wilson_interval
from puckboard.transfer.radius import GridPoint, robustness_radius, seeds_for_lower_bound


def grid(*counts: tuple[float, int, int]) -> list[GridPoint]:
    return [GridPoint(k, n, scale=scale) for scale, k, n in counts]


def test_the_radius_ends_at_the_first_scale_that_falls_below():
    """19 of 20 is 95 %: it keeps the rate; 18 of 20 (90 %) does not, and the 20 of 20 at
    ×4 beyond it claims nothing."""
    r = robustness_radius(grid((1, 20, 20), (2, 19, 20), (3, 18, 20), (4, 20, 20)))
    assert r.radius == 2
    assert (r.at.scale, r.at.successes) == (2, 19)
    assert (r.beyond.scale, r.beyond.successes) == (3, 18)
    assert r.complete and not r.censored


def test_a_grid_kept_to_its_end_gives_a_censored_radius():
    r = robustness_radius(grid((1, 10, 10), (2, 10, 10), (3, 10, 10)))
    assert (r.radius, r.beyond, r.censored) == (3, None, True)


def test_a_design_model_below_the_threshold_has_no_radius():
    r = robustness_radius(grid((1, 18, 20), (2, 20, 20)))
    assert (r.radius, r.at) == (None, None)
    assert r.beyond.scale == 1 and r.complete and not r.censored


def test_a_point_not_run_stops_the_walk_and_marks_it_incomplete():
    r = robustness_radius(grid((1, 20, 20), (2, 0, 0), (3, 20, 20)))
    assert (r.radius, r.beyond, r.complete, r.censored) == (1, None, False, False)
    assert robustness_radius(grid((1, 0, 0))).radius is None
    assert robustness_radius([]).complete is False


def test_by_the_lower_bound_twenty_of_twenty_is_not_enough():
    """20/20 has a Wilson lower bound of 20 / (20 + 1.96²) = 0.839: below 95 %."""
    r = robustness_radius(grid((1, 20, 20), (2, 20, 20)), by="lower")
    assert (r.radius, r.beyond.scale) == (None, 1)


def test_the_two_readings_differ_where_one_failure_in_eighty_is_seen():
    """80/80: lower bound 80 / 83.84 = 0.954 keeps 95 %. 79/80: point estimate 98.75 %
    keeps it, its lower bound (0.933 by the Wilson formula) does not."""
    counts = grid((1, 80, 80), (2, 79, 80))
    assert wilson_interval(80, 80)[0] == pytest.approx(80 / (80 + 1.959963984540054**2))
    assert wilson_interval(79, 80)[0] == pytest.approx(0.93254, abs=1e-4)
    estimate = robustness_radius(counts, by="estimate")
    lower = robustness_radius(counts, by="lower")
    assert (estimate.radius, estimate.censored) == (2, True)
    assert (lower.radius, lower.beyond.scale) == (1, 2)


def test_the_threshold_is_a_parameter():
    counts = grid((1, 10, 10), (2, 9, 10), (3, 8, 10))
    assert robustness_radius(counts, threshold=0.8).radius == 3
    assert robustness_radius(counts, threshold=0.9).radius == 2
    assert robustness_radius(counts, threshold=1.0).radius == 1


def test_seeds_for_the_lower_bound_at_95_percent_is_73():
    """n / (n + z²) ≥ 0.95 ⇔ n ≥ 0.95 · 3.8415 / 0.05 = 72.99."""
    assert seeds_for_lower_bound(0.95) == 73
    assert wilson_interval(73, 73)[0] >= 0.95 > wilson_interval(72, 72)[0]


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [({"by": "median"}, "by must be one of"), ({"threshold": 0}, "threshold must be in")],
)
def test_bad_readings_are_refused(kwargs, message):
    with pytest.raises(ValueError, match=message):
        robustness_radius(grid((1, 1, 1)), **kwargs)
