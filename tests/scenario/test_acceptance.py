"""Faithfulness: the thesis's findings (§4.2, Figure 4.6) as acceptance tests.

Each episode runs the shipped scene with its default noise; outcomes come from the judge
(docs/scenarios.md). The measured outcomes are recorded in docs/controllers.md: over
seeds 0-199 the improved controller succeeds on 80 %, and every failure is the robot that
dodges to the outside of the loop losing the line after a clean pass. The tests hold
that finding (the meeting always works, the failure has one cause, a line-search layer
fixes it) rather than the exact outcome of each seed.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from puckboard.behaviours import load_controller
from puckboard.control.episode import Episode, run_episode
from puckboard.scenario.judge import FAILURES

TUTORIAL = Path(__file__).resolve().parents[2] / "docs" / "tutorial.md"

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


#: The robot that travels clockwise round the counter-clockwise loop: its left-first
#: dodge takes it to the outside, where the loop bends away from it.
OUTSIDE_ROBOT = "right"


@pytest.mark.slow
def test_improved_passes_two_robot_pass_on_most_seeds(improved_runs):
    """Measured: 159 of seeds 0..199 (80 %, 95 % interval 73-85 %), 19 of seeds 0..19.
    The floor, 13 of 20, is far enough below that only a real regression trips it."""
    successes = sum(r.success for r in improved_runs.values())
    assert successes >= 13, {s: r.failure for s, r in improved_runs.items()}


@pytest.mark.slow
def test_improved_loses_only_the_robot_that_dodged_outside_the_loop(improved_runs):
    """Every failure has the one cause docs/controllers.md explains: after a clean pass
    the robot on the outside of the loop leaves the mutual rotation parallel to the line
    and never sees it again. Never a collision, never the robot on the inside."""
    for seed, result in improved_runs.items():
        if result.success:
            continue
        assert result.failure == "lost_line", (seed, result.failure)
        lost = {e.robot for e in result.events if e.kind == "lost_line"}
        assert lost == {OUTSIDE_ROBOT}, (seed, result.events)
        assert all(m.collisions == 0 for m in result.robots), seed


@pytest.mark.slow
def test_improved_passes_without_noise_as_in_the_thesis_v_rep_run():
    """V-REP's physics is deterministic: the thesis saw one outcome per start placement.
    The noise-free embedded run is that outcome, and it is a pass."""
    quiet = {f"noise.{k}": 0.0 for k in ("wheel_speed", "proximity", "ground", "start_jitter")}
    result = run_episode("two-robot-pass", controller="improved", overrides=quiet)
    assert result.success, (result.failure, result.events)


def tutorial_controller_file(tmp_path: Path) -> Path:
    """The tutorial's ``my_controller.py`` block, saved as the reader is told to."""
    text = TUTORIAL.read_text(encoding="utf-8")
    blocks = re.findall(r"^```python\n(# my_controller\.py\n.*?)^```", text, re.M | re.S)
    assert len(blocks) == 1, "the tutorial should have exactly one '# my_controller.py' block"
    path = tmp_path / "my_controller.py"
    path.write_text(blocks[0], encoding="utf-8")
    return path


@pytest.mark.slow
def test_one_line_search_layer_recovers_the_seeds_improved_loses(improved_runs, tmp_path):
    """The failure is the controller's, not the scene's: the tutorial's controller (the
    improved layers plus ``FindLineOnTheRight``) passes exactly where improved failed."""
    lost = [s for s, r in improved_runs.items() if not r.success]
    if not lost:
        pytest.skip("improved passed every seed; nothing to recover")
    spec = f"{tutorial_controller_file(tmp_path)}:my_controller"
    load_controller(spec)  # a bad spec fails here, with its own message
    for seed in lost:
        result = run_episode("two-robot-pass", controller=spec, seed=seed)
        assert result.success, (seed, result.failure, result.events)


@pytest.mark.slow
@pytest.mark.xfail(
    strict=True,
    reason=(
        "measured: improved succeeds on 19 of seeds 0..19 (159 of 0..199); on seed 8 the "
        "robot on the outside of the loop leaves the mutual rotation parallel to the line, "
        "a few cm beside it, and never finds it again (lost_line). See docs/controllers.md."
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


@pytest.mark.slow
def test_stock_robots_meeting_in_a_bend_drive_off_side_by_side():
    """The thesis's Figure 4.6: met at an angle, the stock robots turn the same way and
    drive on side by side, heading the same way, off the line (measured: all of seeds
    0..39 at 20 s; docs/controllers.md)."""
    side_by_side = 0
    for seed in range(5):
        episode = Episode("two-robot-pass-bend", controller="stock", seed=seed)
        result = episode.run(duration=20.0, stop_early=False)
        assert not any(m.passed_other for m in result.robots), seed
        (x0, y0, th0), (x1, y1, th1) = episode.world.poses.tolist()
        close = math.hypot(x1 - x0, y1 - y0) < 0.12
        same_way = abs(math.remainder(th1 - th0, math.tau)) < math.radians(45)
        # heading away from the loop (the east bend's centre is at x = 0.4)
        outward = min(x0, x1) > 0.65 + 0.05 and math.cos(th0) > 0.5 and math.cos(th1) > 0.5
        side_by_side += close and same_way and outward
    assert side_by_side >= 4


@pytest.mark.slow
def test_improved_robots_meeting_in_a_bend_pass_each_other():
    for seed in range(5):
        result = run_episode("two-robot-pass-bend", controller="improved", seed=seed)
        assert all(m.passed_other for m in result.robots), (seed, result.failure, result.events)
        assert result.failure not in MEETING_FAILURES, (seed, result.failure)
