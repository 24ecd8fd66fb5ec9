"""The Wilson score interval against values worked out by hand (z = 1.96, 95 %)."""

from __future__ import annotations

import pytest

from puckboard.sweep.stats import wilson_interval

# Worked by hand from the closed forms, independently of the implementation:
#   0/n  → [0, z²/(n+z²)]        = [0, 3.8415/13.8415] = [0, 0.27753]
#   n/n  → [n/(n+z²), 1]         = [10/13.8415, 1]      = [0.72247, 1]
#   7/10 → centre (0.7 + 0.19207)/1.38415 = 0.64449,
#          half 1.41601·sqrt(0.021 + 0.0096037) = 0.24772 → [0.39677, 0.89221]
HAND = {
    (0, 10): (0.0, 0.27753),
    (10, 10): (0.72247, 1.0),
    (7, 10): (0.39677, 0.89221),
    # 5/10 is symmetric about 0.5: half = (1.95996/1.38415)·sqrt(0.025 + 0.0096037)
    #                              = 1.41601 · 0.186021 = 0.26341
    (5, 10): (0.23659, 0.76341),
    # 0/1: z²/(1+z²) = 3.8415/4.8415 = 0.79345
    (0, 1): (0.0, 0.79345),
}


@pytest.mark.parametrize(("counts", "expected"), list(HAND.items()))
def test_wilson_matches_hand_computed_values(counts, expected):
    low, high = wilson_interval(*counts)
    assert low == pytest.approx(expected[0], abs=2e-5)
    assert high == pytest.approx(expected[1], abs=2e-5)


def test_wilson_is_symmetric_and_contains_the_estimate():
    for n in (1, 3, 10, 37):
        for k in range(n + 1):
            low, high = wilson_interval(k, n)
            assert 0.0 <= low <= k / n <= high <= 1.0
            mirror_low, mirror_high = wilson_interval(n - k, n)
            assert low == pytest.approx(1.0 - mirror_high, abs=1e-12)
            assert high == pytest.approx(1.0 - mirror_low, abs=1e-12)


def test_wilson_narrows_with_more_trials():
    widths = [wilson_interval(7 * m, 10 * m) for m in (1, 4, 16)]
    spans = [high - low for low, high in widths]
    assert spans[0] > spans[1] > spans[2]


def test_wilson_without_trials_is_uninformative_and_bad_counts_fail():
    assert wilson_interval(0, 0) == (0.0, 1.0)
    with pytest.raises(ValueError, match="successes <= trials"):
        wilson_interval(3, 2)
    with pytest.raises(ValueError):
        wilson_interval(-1, 2)


def test_every_report_holds_a_pass_rate_one_way():
    """A sweep's group, a transfer grid's point, a study's cell and a sensitivity bin are
    each a PassRate: the same counts give the same rate, interval and --json names."""
    from puckboard.sensitivity.joint.estimate import Bin
    from puckboard.sweep.stats import PassRate
    from puckboard.sweep.summary import GroupSummary
    from puckboard.transfer.radius import GridPoint
    from puckboard.tune.objective import Cell, CellRate

    plain = PassRate(17, 20)
    assert (plain.rate, plain.interval) == (0.85, wilson_interval(17, 20))
    held = [
        GroupSummary(17, 20, controller="c", params={}),
        GridPoint(17, 20, scale=2.0),
        CellRate(17, 20, cell=Cell("s")),
        Bin(17, 20, low=0, high=1, progress=0, progress_low=0, progress_high=0),
    ]
    for rate in held:
        assert isinstance(rate, PassRate)
        assert (rate.rate, rate.interval) == (plain.rate, plain.interval)
        assert plain.rate_dict().items() <= rate.rate_dict().items()
    assert PassRate(0, 0).rate == 0.0 and PassRate(0, 0).interval == (0.0, 1.0)
