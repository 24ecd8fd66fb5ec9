"""``puckboard.tune``: the search space, the objective's order, the stored study
(determinism, resuming, Ctrl-C) on short episodes run in this process."""

from __future__ import annotations

import dataclasses
import itertools
import re

import pytest
from sweep_helpers import DURATION, CountingExecutor

from puckboard.scenario.scenefile import load_scene
from puckboard.sweep.rows import Outcome
from puckboard.tune import (
    Cell,
    CellRate,
    Interrupted,
    Param,
    Score,
    SpaceError,
    StudyMismatch,
    TuneSpec,
    check_space,
    format_result,
    objective,
    parse_param,
    plot_tune,
    result_dict,
    run_tune,
)
from puckboard.tune.objective import cell_rates, rounds

INNER = "layer.LineFollow.inner_factor"


# -- the search space ------------------------------------------------------------------------
def test_ranges_are_real_whole_or_logarithmic_and_factory_keywords_become_controller_ones():
    assert parse_param(f"{INNER}=0.1:0.9") == Param(INNER, 0.1, 0.9)
    assert parse_param("layer.X.n=1:9:int") == Param("layer.X.n", 1, 9, integer=True)
    assert parse_param("speed=0.5:4:log") == Param("controller.speed", 0.5, 4, log=True)
    both = parse_param("layer.X.n=1:64:int:log")
    assert (both.integer, both.log, both.spec) == (True, True, "layer.X.n=1:64:int:log")
    assert parse_param("speed=0.5:4:log").label == "speed"


@pytest.mark.parametrize(
    ("text", "words"),
    [
        (f"{INNER}=0.9:0.1", "reversed; write the smaller end first"),
        (f"{INNER}=0.5:0.5", "the range is empty"),
        (f"{INNER}=0:1:log", "a log range needs LOW > 0"),
        (f"{INNER}=0.1:0.9:fast", "give int, log or int:log"),
        ("layer.X.n=1.5:3:int", "whole numbers at both ends"),
        (f"{INNER}=a:b", "must be numbers"),
        (INNER, "expected PATH=LOW:HIGH"),
    ],
)
def test_a_bad_range_is_refused_with_what_to_write(text, words):
    with pytest.raises(SpaceError, match=words):
        parse_param(text)


def test_an_unknown_parameter_is_refused_naming_the_keywords_and_the_attributes():
    with pytest.raises(SpaceError) as caught:
        check_space([parse_param("layer.LineFollow.inner=0.1:0.9")], "improved")
    message = str(caught.value)
    assert "factory's keywords: speed" in message
    assert INNER in message and "layer.FrontObstacleLeftTurn.turn_speed" in message
    check_space([parse_param("speed=1:3"), parse_param(f"{INNER}=0.1:0.9")], "improved")


# -- the objective ---------------------------------------------------------------------------
def rates(*cells: tuple[int, float], n: int = 4) -> list[CellRate]:
    return [
        CellRate(wins, n, cell=Cell("s", str(i)), progress_laps=progress)
        for i, (wins, progress) in enumerate(cells)
    ]


def test_the_worst_cell_decides_then_the_mean_then_progress():
    robust = Score.of(rates((2, 0.1), (2, 0.1)))  # 50 % everywhere
    lopsided = Score.of(rates((4, 3.0), (1, 3.0)))  # better on average, worse at its worst
    assert robust > lopsided and robust.value > lopsided.value
    higher_mean = Score.of(rates((2, 0.0), (4, 0.0)))
    assert higher_mean > robust and higher_mean.value > robust.value
    further = Score.of(rates((2, 0.2), (2, 0.2)))
    assert further > robust and further.value > robust.value


def test_the_single_number_optuna_maximises_orders_every_score_as_the_score_does():
    progress = (0.0, 0.3, 1.0, 9.0)
    scores = [
        Score.of(rates((a, p), (b, q)))
        for a, b in itertools.product(range(5), repeat=2)
        for p, q in itertools.product(progress, repeat=2)
    ]
    for one, other in itertools.combinations(scores, 2):
        if one == other:
            continue
        assert (one < other) == (one.value < other.value), (one, other)


def test_rates_are_counted_per_cell_and_rounds_cover_the_seeds_once():
    cells = [Cell("a", "epuck"), Cell("a", "epuck-vrep")]

    def outcome(seed, success, progress):
        return Outcome(str(seed), "c", (), seed, success, "", progress, 0.0)

    pairs = [(cells[0], outcome(0, True, 1.0)), (cells[0], outcome(1, False, 0.0))]
    pairs += [(cells[1], outcome(0, True, 2.0))]
    first, second = cell_rates(pairs, cells)
    assert (first.successes, first.episodes, first.progress_laps) == (1, 2, 0.5)
    assert (second.rate, second.interval[1]) == (1.0, 1.0)
    cut = rounds(range(10, 20), 4)
    assert [list(r) for r in cut] == [[10, 11], [12, 13, 14], [15, 16], [17, 18, 19]]
    assert rounds(range(2), 4) == [range(0, 1), range(1, 2)]


# -- studies on short episodes ---------------------------------------------------------------
@pytest.fixture(scope="module")
def short_pass():
    """The two-robot pass cut to a few seconds: every episode fails, quickly."""
    return dataclasses.replace(load_scene("two-robot-pass"), duration=DURATION)


def spec_for(scene, **changes) -> TuneSpec:
    base = dict(
        scenes=(scene,),
        controller="improved",
        params=(parse_param(f"{INNER}=0.1:0.9"), parse_param("speed=1:3")),
        seeds=range(2),
        validate=range(2, 3),
        rounds=2,
    )
    return TuneSpec(**{**base, **changes})


def drawn(result) -> list[tuple[str, dict]]:
    return [(t["state"], t["params"]) for t in result.trials]


def test_the_first_trial_is_the_controller_as_shipped_and_the_same_seed_draws_the_same(short_pass):
    one = run_tune(spec_for(short_pass), 3, executor=CountingExecutor())
    two = run_tune(spec_for(short_pass), 3, executor=CountingExecutor())
    assert drawn(one) == drawn(two)
    assert one.trials[0]["params"] == {INNER: 0.2, "speed": pytest.approx(2.0943951023931953)}
    other = run_tune(spec_for(short_pass, sampler_seed=1), 3, executor=CountingExecutor())
    assert drawn(other)[0] == drawn(one)[0] and drawn(other)[1:] != drawn(one)[1:]


def test_a_resumed_study_skips_finished_trials_and_draws_what_one_run_would(short_pass, tmp_path):
    study = tmp_path / "tune.journal"
    through = run_tune(spec_for(short_pass), 3, executor=CountingExecutor())
    first = run_tune(spec_for(short_pass), 2, executor=CountingExecutor(), study_path=study)
    executor = CountingExecutor()
    resumed = run_tune(spec_for(short_pass), 3, executor=executor, study_path=study)
    assert (first.ran, resumed.ran, resumed.skipped) == (2, 1, 2)
    assert drawn(resumed) == drawn(through)
    # the new trial's 2 design seeds only: the best is still trial 0 (every short episode
    # fails, and ties go to the earlier), whose validation the study kept
    assert len(executor.ran) == 2
    assert [r.to_dict() for r in resumed.validation] == [r.to_dict() for r in first.validation]
    again = run_tune(
        spec_for(short_pass), 3, executor=(idle := CountingExecutor()), study_path=study
    )
    assert (again.ran, again.skipped, idle.ran) == (0, 3, [])
    assert [r.to_dict() for r in again.validation] == [r.to_dict() for r in resumed.validation]


def test_ctrl_c_keeps_the_finished_trials_and_the_interrupted_one_runs_again(
    short_pass, tmp_path, monkeypatch
):
    study = tmp_path / "tune.journal"
    through = run_tune(spec_for(short_pass), 3, executor=CountingExecutor())
    calls = []
    real = objective.run_cells

    def interrupted_in_the_second_trial(*args, **kwargs):
        calls.append(1)
        if len(calls) == 3:  # trial 0 ran two rounds; this is trial 1's first
            raise Interrupted()
        return real(*args, **kwargs)

    monkeypatch.setattr("puckboard.tune.run.run_cells", interrupted_in_the_second_trial)
    with pytest.raises(KeyboardInterrupt):
        run_tune(spec_for(short_pass), 3, executor=CountingExecutor(), study_path=study)
    monkeypatch.setattr("puckboard.tune.run.run_cells", real)
    resumed = run_tune(spec_for(short_pass), 3, executor=CountingExecutor(), study_path=study)
    assert (resumed.skipped, resumed.ran) == (1, 2)
    assert drawn(resumed) == drawn(through)
    # the interrupted trial never finished: numbered as the trials that ran through are
    assert [t["number"] for t in resumed.trials] == [t["number"] for t in through.trials]
    assert resumed.best["number"] == through.best["number"]


def test_the_same_params_in_another_order_resume_the_study_and_draw_what_it_drew(
    short_pass, tmp_path
):
    study = tmp_path / "tune.journal"
    through = run_tune(spec_for(short_pass), 3, executor=CountingExecutor())
    run_tune(spec_for(short_pass), 2, executor=CountingExecutor(), study_path=study)
    swapped = spec_for(short_pass, params=spec_for(short_pass).params[::-1])
    resumed = run_tune(swapped, 3, executor=CountingExecutor(), study_path=study)
    assert (resumed.skipped, resumed.ran) == (2, 1)
    assert drawn(resumed) == drawn(through)
    assert resumed.spec.params == through.spec.params  # the order that made the study


def test_trials_another_command_ran_on_the_study_meanwhile_are_counted_as_such(
    short_pass, tmp_path
):
    study = tmp_path / "tune.journal"
    others = []

    def another_command_runs_one(event):
        if not others:  # after this command's first trial, another runs the study to 2
            others.append(run_tune(spec_for(short_pass), 2, executor=CountingExecutor(),
                                   study_path=study))  # fmt: skip

    result = run_tune(
        spec_for(short_pass), 3, executor=CountingExecutor(), study_path=study,
        on_trial=another_command_runs_one,
    )  # fmt: skip
    assert (others[0].ran, others[0].skipped) == (1, 1)
    assert (len(result.trials), result.ran, result.skipped, result.alongside) == (3, 2, 0, 1)
    assert [t["number"] for t in result.trials] == [0, 1, 2]
    assert format_result(result, stored="conc.journal").startswith(
        "3 trials (2 run now, 0 from conc.journal, 1 by another command on it meanwhile; "
    )
    assert result_dict(result)["run_alongside"] == 1


def test_a_damaged_study_file_is_refused_saying_what_its_whole_lines_hold(short_pass, tmp_path):
    study = tmp_path / "tune.journal"
    run_tune(spec_for(short_pass), 2, executor=CountingExecutor(), study_path=study)
    whole = study.read_bytes().splitlines(keepends=True)
    n = len(whole)
    cases = [
        # a copy cut short in its last line (the validation's): both trials are whole
        (whole[:-1] + [whole[-1][:10]], f"line {n} of {n} is cut short; the {n - 1} whole "
         "lines before it hold 2 finished trials"),
        # a line that is no journal's before the first trial ended
        (whole[:2] + [b"#garbage\n"] + whole[2:], f"line 3 of {n + 1} is not a journal line; "
         "the 2 whole lines before it hold 0 finished trials"),
    ]  # fmt: skip
    for number, (lines, words) in enumerate(cases):
        damaged = tmp_path / f"damaged{number}.journal"
        damaged.write_bytes(b"".join(lines))
        with pytest.raises(StudyMismatch) as caught:
            run_tune(spec_for(short_pass), 3, executor=CountingExecutor(), study_path=damaged)
        assert f"--study '{damaged}' is damaged: {words}" in str(caught.value)
        assert damaged.read_bytes() == b"".join(lines)  # nothing appended to it
    for text, words in ((whole[0][:30], "damaged: line 1 of 1 is cut short; the 0 whole"),
                        (b"no journal, no newline", "is not a study file")):  # fmt: skip
        other = tmp_path / "other.journal"
        other.write_bytes(text)
        with pytest.raises(StudyMismatch, match=words):
            run_tune(spec_for(short_pass), 1, executor=CountingExecutor(), study_path=other)
        assert other.read_bytes() == text


def test_a_study_made_by_another_command_is_refused_naming_what_differs(short_pass, tmp_path):
    study = tmp_path / "tune.journal"
    run_tune(spec_for(short_pass), 1, executor=CountingExecutor(), study_path=study)
    with pytest.raises(
        StudyMismatch, match=r"made by another command \(seeds: \"0:2\" there, \"0:1\" now\)"
    ):
        run_tune(
            spec_for(short_pass, seeds=range(1)), 1, executor=CountingExecutor(), study_path=study
        )
    (tmp_path / "notes.txt").write_text("not a study\n")
    with pytest.raises(StudyMismatch, match="not a study file"):
        run_tune(
            spec_for(short_pass), 1, executor=CountingExecutor(), study_path=tmp_path / "notes.txt"
        )


def test_design_and_validation_seeds_may_not_overlap(short_pass):
    with pytest.raises(ValueError, match="share 1 seeds \\(first 1\\)"):
        spec_for(short_pass, validate=range(1, 3))


def test_the_report_gives_both_rates_per_cell_and_a_line_to_run_it(short_pass, tmp_path):
    spec = spec_for(short_pass, profiles=("epuck", "epuck-vrep"))
    result = run_tune(spec, 2, executor=CountingExecutor())
    data = result_dict(result)
    assert [(c["profile"], c["episodes"]) for c in data["design"]] == [
        ("epuck", 2),
        ("epuck-vrep", 2),
    ]
    assert [(c["profile"], c["episodes"]) for c in data["validation"]] == [
        ("epuck", 1),
        ("epuck-vrep", 1),
    ]
    best = data["best"]["params"]
    assert (
        data["use"] == f"--controller improved --set {INNER}={best[INNER]:.6g} "
        f"--set controller.speed={best['speed']:.6g}"
    )
    text = format_result(result)
    assert "design (seeds 0:2)" in text and "validation (seeds 2:3)" in text
    assert data["use"] in text
    plot_tune(result, tmp_path / "tune.png")
    assert (tmp_path / "tune.png").stat().st_size > 0
    import matplotlib

    with matplotlib.rc_context({"svg.fonttype": "none"}):  # text kept as text
        plot_tune(result, tmp_path / "tune.svg")
    svg = (tmp_path / "tune.svg").read_text(encoding="utf-8")
    assert "a hint, not a finding" in svg  # 2 trials: the importances carry the caveat
    ticks = re.findall(r">(-?\d+(?:\.\d+)?)</text>", svg)
    assert "1" in ticks and "0.5" not in ticks  # trials are counted: whole-number ticks


def test_validation_below_design_beyond_both_intervals_is_overfitting(short_pass):
    result = run_tune(spec_for(short_pass), 1, executor=CountingExecutor())
    cell = result.design[0].cell
    result.design = [CellRate(40, 40, cell=cell)]
    result.validation = [CellRate(30, 40, cell=cell)]
    assert result.overfit() == [cell]
    assert "validation is below design beyond both intervals" in format_result(result)
    result.validation = [CellRate(38, 40, cell=cell)]  # lower, within the intervals
    assert result.overfit() == []


def test_a_factory_keyword_is_an_episode_parameter_checked_before_any_run(short_pass):
    from puckboard.control.episode import Episode
    from puckboard.sweep import PlanError, SweepPlan, check_plan

    episode = Episode(short_pass, controller="improved", overrides={"controller.speed": 1.25})
    try:
        assert {c.find("Cruise").speed for c in episode.controllers.values()} == {1.25}
    finally:
        episode.connection.close()
    plan = SweepPlan("two-robot-pass", ("improved",), range(1), {"controller.speed": (1.0, 2.0)})
    assert check_plan(plan, short_pass) == []
    typo = SweepPlan("two-robot-pass", ("improved",), range(1), {"controller.sped": (1.0,)})
    with pytest.raises(PlanError, match="unexpected keyword argument 'sped'"):
        check_plan(typo, short_pass)
