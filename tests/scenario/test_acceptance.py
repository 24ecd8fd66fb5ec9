"""Faithfulness: the thesis's findings (§4.2, Figure 4.6) as acceptance tests.

Each episode runs the shipped scene with its default noise; outcomes come from the judge
(docs/scenarios.md). The measured outcomes are recorded in docs/controllers.md.
"""

from __future__ import annotations

import pytest

from puckboard.episode import run_episode
from puckboard.sim.judge import FAILURES

IMPROVED_SEEDS = range(20)
STOCK_SEEDS = range(10)
#: Failures that mean "the meeting itself went wrong": what the thesis reports for the
#: stock controller (turn the same way and drive side by side, or drive into each other).
MEETING_FAILURES = {"parallel_driving", "stuck", "collision"}


@pytest.fixture(scope="module")
def improved_runs():
    return {s: run_episode("two-robot-pass", controller="improved", seed=s) for s in IMPROVED_SEEDS}


@pytest.fixture(scope="module")
def stock_runs():
    return {s: run_episode("two-robot-pass", controller="stock", seed=s) for s in STOCK_SEEDS}


@pytest.mark.slow
def test_improved_robots_meet_and_pass_each_other_on_every_seed(improved_runs):
    """The thesis's fix (always turn left first) removes the stock failure: the robots go
    past each other right side to right side, without touching or driving side by side."""
    for seed, result in improved_runs.items():
        assert all(m.passed_other for m in result.robots), (seed, result.failure, result.events)
        assert result.failure not in MEETING_FAILURES, (seed, result.failure)


@pytest.mark.slow
def test_improved_passes_two_robot_pass_on_nearly_every_seed(improved_runs):
    """The measured level (docs/controllers.md, 'Measured outcomes'): 19 of seeds 0..19."""
    failures = {s: r.failure for s, r in improved_runs.items() if not r.success}
    assert len(failures) <= 1, failures
    assert set(failures.values()) <= {"lost_line"}, failures


@pytest.mark.slow
@pytest.mark.xfail(
    strict=True,
    reason=(
        "measured: improved succeeds on 19 of seeds 0..19; on seed 8 the robot on the "
        "outside of the loop leaves the mutual rotation parallel to the line, a few cm "
        "beside it, and never finds it again (lost_line). See docs/controllers.md."
    ),
)
def test_improved_passes_two_robot_pass_on_every_seed(improved_runs):
    failures = {s: r.failure for s, r in improved_runs.items() if not r.success}
    assert not failures


@pytest.mark.slow
def test_stock_fails_at_the_meeting_for_most_seeds(stock_runs):
    failed = {s: r.failure for s, r in stock_runs.items() if not r.success}
    assert len(failed) >= 8, failed
    assert set(failed.values()) <= set(FAILURES)
    at_meeting = [
        s
        for s, r in stock_runs.items()
        if r.failure in MEETING_FAILURES and not any(m.passed_other for m in r.robots)
    ]
    assert len(at_meeting) >= 8, {s: stock_runs[s].failure for s in STOCK_SEEDS}


@pytest.mark.slow
@pytest.mark.parametrize("controller", ["stock", "improved"])
def test_either_controller_alone_follows_the_line_for_several_laps(controller):
    result = run_episode("line-follow", controller=controller, seed=0)
    assert result.success, (result.failure, result.events)
    (robot,) = result.robots
    assert robot.progress_laps >= 2.5
    assert robot.on_line_fraction > 0.95
    assert robot.collisions == 0
