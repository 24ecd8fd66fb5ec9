"""Faithfulness: the thesis's findings (§4.2, Figure 4.6) as acceptance tests, per profile.

Each episode runs the shipped scene with its default noise, once with V-REP's e-puck model
(``epuck-vrep``, the scenes' own profile: the thesis measured on it) and once with the
physical e-puck (``epuck``); outcomes come from the judge (docs/scenarios.md). The
measured rates, 200 seeds per cell with 95 % intervals, are in docs/controllers.md. The
tests hold what was measured (the meeting always works, the failure has one kind, floors
well below the measured rates) rather than the exact outcome of each seed; the thesis's
claims that the measurements contradict stay as strict expected failures.
"""

from __future__ import annotations

import math

import pytest
from episodes import episode, episodes
from tutorial_file import tutorial_controller_path

from puckboard.behaviours import load_controller
from puckboard.control.episode import Episode
from puckboard.scenario.judge import FAILURES

IMPROVED_SEEDS = range(20)
STOCK_SEEDS = range(10)
PROFILES = ("epuck-vrep", "epuck")
#: Failures that mean "the meeting itself went wrong": what the thesis reports for the
#: stock controller (turn the same way and drive side by side, or drive into each other).
MEETING_FAILURES = {"parallel_driving", "stuck", "collision"}
QUIET = {f"noise.{k}": 0.0 for k in ("wheel_speed", "proximity", "ground", "start_jitter")}


def run(scene, controller, seed=0, profile="epuck-vrep", **overrides):
    """One episode, run once per session (the pages' claims tests look at the same ones)."""
    return episode(scene, controller, seed, profile, overrides)


def runs_by_seed(scene, controller, seeds, profile, overrides=None):
    """Episodes by seed, run once per session and shared between the worker processes."""
    seeds = list(seeds)
    return dict(zip(seeds, episodes(scene, controller, seeds, profile, overrides)))


@pytest.fixture(scope="module", params=PROFILES)
def improved_runs(request):
    profile = request.param
    return profile, runs_by_seed("two-robot-pass", "improved", IMPROVED_SEEDS, profile)


@pytest.fixture(scope="module", params=PROFILES)
def stock_runs(request):
    profile = request.param
    return profile, runs_by_seed("two-robot-pass", "stock", STOCK_SEEDS, profile)


@pytest.mark.slow
def test_improved_robots_meet_and_pass_each_other_on_every_seed(improved_runs):
    """The thesis's fix (always turn left first) removes the stock failure: the robots go
    past each other right side to right side, without touching or driving side by side,
    with either profile."""
    profile, runs = improved_runs
    for seed, result in runs.items():
        assert all(m.passed_other for m in result.robots), (profile, seed, result.events)
        assert not set(result.failures) & MEETING_FAILURES, (profile, seed, result.failures)
        assert all(m.profile == profile for m in result.robots)


#: The robot that travels clockwise round the counter-clockwise loop: its left-first
#: dodge takes it to the outside, where the loop bends away from it.
OUTSIDE_ROBOT = "right"


@pytest.mark.slow
@pytest.mark.parametrize("improved_runs", ["epuck-vrep"], indirect=True)
def test_improved_passes_two_robot_pass_on_most_seeds_with_vrep_s_model(improved_runs):
    """Measured with epuck-vrep: 133 of seeds 0..199 (66.5 %, 95 % interval 60-73 %), 15 of
    seeds 0..19. The floor, 10 of 20, is far enough below that only a real regression
    trips it."""
    _, runs = improved_runs
    successes = sum(r.success for r in runs.values())
    assert successes >= 10, {s: r.failure for s, r in runs.items()}


@pytest.mark.slow
@pytest.mark.xfail(
    strict=True,
    reason=(
        "measured with the physical e-puck (epuck): improved finds the line again on 15 of "
        "seeds 0..199 (7.5 %, 95 % interval 5-12 %), 1 of 0..19; the robots pass each other "
        "cleanly every time and then lose the line (lost_line). See docs/controllers.md."
    ),
)
def test_improved_passes_two_robot_pass_on_most_seeds_with_the_physical_e_puck():
    runs = episodes("two-robot-pass", "improved", IMPROVED_SEEDS, "epuck")
    assert sum(r.success for r in runs) >= 10, [r.failure for r in runs]


@pytest.mark.slow
def test_improved_fails_only_by_losing_the_line_after_the_pass(improved_runs):
    """Every failure is ``lost_line`` after a clean pass (docs/controllers.md explains why):
    never a collision, never a failure at the meeting."""
    profile, runs = improved_runs
    for seed, result in runs.items():
        if result.success:
            continue
        assert result.failures == ["lost_line"], (profile, seed, result.failures)
        assert all(m.collisions == 0 for m in result.robots), (profile, seed)


@pytest.mark.slow
def test_it_is_always_the_robot_outside_the_loop_that_loses_the_line(improved_runs):
    """Measured: every lost_line of 200 seeds × 2 scenes × 2 profiles is the robot ``right``."""
    profile, runs = improved_runs
    for seed, result in runs.items():
        if not result.success:
            lost = {e.robot for e in result.events if e.kind == "lost_line"}
            assert lost == {OUTSIDE_ROBOT}, (profile, seed, result.events)


@pytest.mark.slow
@pytest.mark.parametrize("scene", ["two-robot-pass", "two-robot-pass-bend"])
def test_improved_passes_without_noise_with_vrep_s_model_as_in_the_thesis_run(scene):
    """V-REP's physics is deterministic: the thesis saw one outcome per start placement.
    The noise-free embedded run with V-REP's model is that outcome, and it is a pass."""
    result = run(scene, "improved", **QUIET)
    assert result.success, (result.failure, result.events)


@pytest.mark.slow
def test_without_noise_the_physical_e_puck_still_loses_the_line():
    """Measured: with the physical e-puck the noise-free run on the straight fails too
    (lost_line); the one in the bend passes."""
    result = run("two-robot-pass", "improved", profile="epuck", **QUIET)
    assert result.failures == ["lost_line"], result.failures
    assert all(m.passed_other for m in result.robots)


@pytest.mark.slow
def test_one_line_search_layer_finds_the_line_on_the_seeds_improved_loses(improved_runs):
    """The failure is the controller's, not the scene's: the tutorial's controller (the
    improved layers plus ``FindLineOnTheRight``) finds the line again where improved lost
    it, with either profile, and with V-REP's model passes. With the physical e-puck a
    robot then grazes the cylinder it has just rounded on some seeds (measured: 119 of
    200, every failure a collision with an obstacle), the only failure it has."""
    profile, runs = improved_runs
    lost = [s for s, r in runs.items() if not r.success]
    if not lost:
        pytest.skip("improved passed every seed; nothing to recover")
    spec = f"{tutorial_controller_path()}:my_controller"
    load_controller(spec)  # a bad spec fails here, with its own message
    for seed, result in runs_by_seed("two-robot-pass", spec, lost, profile).items():
        assert "lost_line" not in result.failures, (profile, seed, result.failures)
        if profile == "epuck-vrep":
            assert result.success, (profile, seed, result.failures, result.events)
        else:
            assert result.success or result.failures == ["collision"], (profile, seed)


@pytest.mark.slow
@pytest.mark.xfail(
    strict=True,
    reason=(
        "measured with the physical e-puck (epuck): the tutorial's controller passes 81 of "
        "seeds 0..199 (40.5 %, 95 % interval 34-47 %), 10 of 0..19; it finds the line again "
        "every time, and on the others a robot grazes the cylinder it has just rounded "
        "(collision). See docs/controllers.md."
    ),
)
def test_the_tutorial_controller_passes_every_seed_with_the_physical_e_puck():
    spec = f"{tutorial_controller_path()}:my_controller"
    failures = {}
    for seed, result in runs_by_seed("two-robot-pass", spec, IMPROVED_SEEDS, "epuck").items():
        if not result.success:
            failures[seed] = result.failures
    assert not failures


@pytest.mark.slow
@pytest.mark.xfail(
    strict=True,
    reason=(
        "measured with V-REP's model (epuck-vrep): improved succeeds on 15 of seeds 0..19 "
        "(133 of 0..199, 66.5 %, 95 % interval 60-73 %); on the others the robot on the outside "
        "of the loop leaves the mutual rotation beside the line and never finds it again "
        "(lost_line). The thesis's 'every seed' does not hold. See docs/controllers.md."
    ),
)
def test_improved_passes_two_robot_pass_on_every_seed():
    runs = runs_by_seed("two-robot-pass", "improved", IMPROVED_SEEDS, "epuck-vrep")
    failures = {s: r.failure for s, r in runs.items() if not r.success}
    assert not failures


@pytest.mark.slow
def test_stock_fails_at_the_meeting_for_most_seeds(stock_runs):
    """Measured: 200 of 200 seeds fail at the meeting with either profile (the robots touch
    before they are past each other; some slide past afterwards, too late)."""
    profile, runs = stock_runs
    failed = {s: r.failure for s, r in runs.items() if not r.success}
    assert len(failed) >= 8, (profile, failed)
    assert set(failed.values()) <= set(FAILURES)

    def failed_at_meeting(result):
        first = result.failures[0] if result.failures else None
        when = result_time(result, first)
        passed = [e.time_s for e in result.events if e.kind == "passed_other"]
        return first in MEETING_FAILURES and (not passed or when < min(passed))

    at_meeting = [s for s, r in runs.items() if failed_at_meeting(r)]
    assert len(at_meeting) >= 8, (profile, {s: runs[s].failures for s in STOCK_SEEDS})


def result_time(result, kind):
    """When failure ``kind`` was first reported among the result's events."""
    return min((e.time_s for e in result.events if e.kind == kind), default=math.inf)


@pytest.mark.slow
@pytest.mark.parametrize("controller", ["stock", "improved"])
def test_either_controller_alone_follows_the_line_for_several_laps(controller):
    result = episode("line-follow", controller, 0)
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
@pytest.mark.parametrize("profile", PROFILES)
def test_the_judge_names_figure_4_6_when_stock_robots_meet_in_a_bend(profile):
    """Measured: parallel_driving is the verdict on 200 of 200 seeds with either profile;
    the touch before it stays in the failures list."""
    for seed, result in runs_by_seed("two-robot-pass-bend", "stock", range(5), profile).items():
        assert result.failure == "parallel_driving", (profile, seed, result.failures)
        assert "parallel_driving" in result.failures


@pytest.mark.slow
@pytest.mark.parametrize("profile", PROFILES)
def test_improved_robots_meeting_in_a_bend_pass_each_other(profile):
    for seed, result in runs_by_seed("two-robot-pass-bend", "improved", range(5), profile).items():
        assert all(m.passed_other for m in result.robots), (profile, seed, result.events)
        assert not set(result.failures) & MEETING_FAILURES, (profile, seed, result.failures)


# -- plausible robots (--variation plausible): the same findings on robots as built ---------
#: Each robot drawn within its profile's plausible ranges, a robot each, seeded by the seed.
VARIED = {"variation": "plausible"}


@pytest.fixture(scope="module", params=PROFILES)
def varied_improved_runs(request):
    profile = request.param
    return profile, runs_by_seed("two-robot-pass", "improved", IMPROVED_SEEDS, profile, VARIED)


@pytest.mark.slow
def test_plausible_improved_robots_still_pass_each_other_on_every_seed(varied_improved_runs):
    """Measured over seeds 0..199 with either profile: the meeting works on all 200 runs;
    the failures come after it: the robot outside the loop loses the line (lost_line),
    or, with the physical robot, one that found the line again grazes the cylinder it
    rounds (collision, 5 of 200, each seconds before passing the obstacle)."""
    profile, runs = varied_improved_runs
    for seed, result in runs.items():
        assert all(m.passed_other for m in result.robots), (profile, seed, result.events)
        assert not set(result.failures) & {"parallel_driving", "stuck"}, (profile, seed)
        first_touch = result_time(result, "collision")
        passed = max(e.time_s for e in result.events if e.kind == "passed_other")
        assert first_touch > passed, (profile, seed, result.events)
        if not result.success:
            assert result.failure in ("lost_line", "collision"), (profile, seed, result.failures)
            lost = {e.robot for e in result.events if e.kind == "lost_line"}
            assert lost <= {OUTSIDE_ROBOT}, (profile, seed, result.events)


@pytest.mark.slow
@pytest.mark.parametrize("varied_improved_runs", ["epuck-vrep"], indirect=True)
def test_plausible_robots_of_vrep_s_model_pass_on_most_seeds(varied_improved_runs):
    """Measured: 138 of seeds 0..199 (69 %, 95 % interval 62-75 %), 15 of 0..19, with
    V-REP's model varied (its one uncertain number: the body's radius, 35.2-36.2 mm).
    The floor, 10 of 20, is the unvaried one's."""
    _, runs = varied_improved_runs
    assert sum(r.success for r in runs.values()) >= 10, {s: r.failure for s, r in runs.items()}


@pytest.mark.slow
@pytest.mark.parametrize("profile", PROFILES)
def test_the_line_search_layer_finds_the_line_on_plausible_robots_too(profile):
    """Measured over seeds 0..199 on plausible robots: the tutorial's controller never
    loses the line with either profile; with V-REP's model it passes all 200, with the
    physical robot 50 (25 %, 95 % interval 20-31 %; 4 of seeds 0..19), every failure a
    robot grazing the cylinder it has just rounded (collision). Floors: 15 of 20 and 1 of
    20."""
    spec = f"{tutorial_controller_path()}:my_controller"
    runs = episodes("two-robot-pass", spec, IMPROVED_SEEDS, profile, VARIED)
    for seed, result in zip(IMPROVED_SEEDS, runs):
        assert all(m.passed_other for m in result.robots), (profile, seed)
        assert "lost_line" not in result.failures, (profile, seed, result.failures)
        assert result.success or result.failure == "collision", (profile, seed, result.failures)
    floor = 15 if profile == "epuck-vrep" else 1
    assert sum(r.success for r in runs) >= floor, [r.failure for r in runs]


@pytest.mark.slow
@pytest.mark.parametrize("profile", PROFILES)
def test_plausible_stock_robots_still_fail_at_the_meeting(profile):
    """Measured over seeds 0..199 on plausible robots: 0 successes with either profile;
    V-REP's model collision 200, the physical one collision 133, parallel_driving 67."""
    runs = runs_by_seed("two-robot-pass", "stock", STOCK_SEEDS, profile, VARIED)
    for seed, result in runs.items():
        assert not result.success, (profile, seed)
        first = result.failures[0]
        passed = [e.time_s for e in result.events if e.kind == "passed_other"]
        assert first in MEETING_FAILURES, (profile, seed, result.failures)
        assert not passed or result_time(result, first) < min(passed), (profile, seed)


@pytest.mark.slow
@pytest.mark.xfail(
    strict=True,
    reason=(
        "measured with the physical e-puck (epuck) under --variation reality-gap, validation "
        "seeds 500..699: robust passes 161 of 200 on the straight meeting (80.5 %, 95 % "
        "interval 74-85 %), 128 in the bend (64 %, 57-70 %), 123 on generated-pass "
        "(61.5 %, 55-68 %); most failures touch an obstacle of IR reflectance 0.15 or less, "
        "first seen closer than the robot drives before its wheels act over a real link. "
        "Near misses too: V-REP's model in the bend 188 of 200 (94 %, 90-97 %), and "
        "generated-pass on plausible physical robots 189 of 200 (94.5 %, 90-97 %). The 95 % "
        "aimed for does not hold. See docs/controllers.md, 'A black obstacle, against the "
        "link'."
    ),
)
def test_robust_passes_plausible_conditions_at_95_percent_with_the_physical_e_puck():
    """The third round's aim, kept visible: 95 % of ten validation seeds is all ten."""
    runs = runs_by_seed(
        "two-robot-pass", "robust", range(500, 510), "epuck", {"variation": "reality-gap"}
    )
    failures = {s: r.failure for s, r in runs.items() if not r.success}
    assert not failures
