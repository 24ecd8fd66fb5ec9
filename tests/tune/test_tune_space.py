"""The search space against the controller it tunes: each parameter's kind is its shipped
value's, a setting that is true/false or a word is searched as a choice, and the
controller is built once to know it. No episode runs here."""

from __future__ import annotations

import math
import shlex

import pytest

from puckboard.tune import Choice, Param, SpaceError, TuneResult, TuneSpec, check_space, parse_param
from puckboard.tune.plot import MIN_TOP_TRIALS, TARGET_QUANTILE, importance_caveat
from puckboard.tune.report import ready_line
from puckboard.tune.space import shipped_values, trial_zero

RATIO = "layer.LineSearch.ratio"


def test_an_int_range_on_a_real_attribute_is_refused_as_it_would_round_the_shipped_value():
    with pytest.raises(SpaceError) as caught:
        check_space([parse_param(f"{RATIO}=0:1:int")], "robust")
    assert str(caught.value) == (
        f"--param {RATIO}=0:1:int: {RATIO} is a real number (ships 0.5); an int range would "
        "round it: drop :int"
    )
    # the real range is accepted, and trial 0 is the value robust ships, as it is
    params = [parse_param(f"{RATIO}=0:1")]
    assert trial_zero(params, check_space(params, "robust")) == {RATIO: 0.5}


def test_trial_zero_is_empty_rather_than_a_shipped_value_changed_to_fit():
    tunable = shipped_values("robust")
    assert tunable.values[RATIO] == 0.5
    assert trial_zero([Param(RATIO, 0, 1, integer=True)], tunable) == {}  # 0.5 is no int
    assert trial_zero([Param(RATIO, 0.6, 1)], tunable) == {}  # outside the range


@pytest.mark.parametrize(
    ("text", "words"),
    [
        (
            "layer.LineFollow.recovery=0:1:int",
            "layer.LineFollow.recovery is true or false, not a number; search it as a choice: "
            "--param layer.LineFollow.recovery=true,false",
        ),
        (
            "layer.ClearanceGuard.side=0:1",
            "layer.ClearanceGuard.side is a word ('right'), not a number; search it as a "
            "choice: list the words to try",
        ),
        (
            "layer.SideWallKeep.sides=0:1",
            "layer.SideWallKeep.sides is a tuple (('right',)), not a number or one value",
        ),
        ("layer.SideWallKeep.sides=a,b", "is a tuple"),
        ("layer.LineFollow.recovery=1,0", "recovery is true or false; every choice must be one"),
        ("layer.ClearanceGuard.side=1,2", "side is a word ('right'); every choice must be one"),
    ],
)
def test_a_setting_that_is_no_number_is_named_for_what_it_is(text, words):
    with pytest.raises(SpaceError) as caught:
        check_space([parse_param(text)], "robust")
    assert words in str(caught.value)
    assert "has no such parameter" not in str(caught.value)


def test_true_false_and_words_are_searched_as_choices_from_the_shipped_values():
    recovery = parse_param("layer.LineFollow.recovery=true,false")
    side = parse_param("layer.ClearanceGuard.side=right,left")
    assert recovery == Choice("layer.LineFollow.recovery", (True, False))
    assert (recovery.spec, side.spec) == (
        "layer.LineFollow.recovery=true,false",
        "layer.ClearanceGuard.side=right,left",
    )
    tunable = check_space([recovery, side], "robust")
    assert trial_zero([recovery, side], tunable) == {
        "layer.LineFollow.recovery": True,
        "layer.ClearanceGuard.side": "right",
    }
    for bad, words in (("x=true,true", "listed twice"), ("x=a,,b", "an empty choice")):
        with pytest.raises(SpaceError, match=words):
            parse_param(bad)


def test_the_controller_is_built_once_to_check_the_space(monkeypatch):
    import puckboard.behaviours as behaviours

    real = behaviours.load_controller
    built = []

    def counted(*args, **kwargs):
        built.append(args)
        return real(*args, **kwargs)

    monkeypatch.setattr(behaviours, "load_controller", counted)
    params = [parse_param(f"{RATIO}=0.1:0.9"), parse_param("speed=1:3")]
    trial_zero(params, check_space(params, "robust"))
    assert len(built) == 1


def test_the_line_to_use_pastes_into_a_shell_whatever_the_path():
    from puckboard.scenario.scenefile import load_scene

    controller = "my lab/contrôleur é.py:make"
    spec = TuneSpec(
        scenes=(load_scene("two-robot-pass"),),
        controller=controller,
        params=(Param(RATIO, 0.1, 0.9), Choice("layer.LineFollow.recovery", (True, False))),
        seeds=range(2),
        validate=range(2, 3),
    )
    best = {"number": 0, "params": {RATIO: 0.25, "layer.LineFollow.recovery": False}}
    line = ready_line(TuneResult(spec, [], {**best, "value": 0.0}, [], []))
    assert shlex.split(line) == [
        "--controller", controller, "--set", f"{RATIO}=0.25",
        "--set", "layer.LineFollow.recovery=false",
    ]  # fmt: skip


def test_importances_of_few_trials_carry_a_caveat_from_the_evaluator_s_own_minimum():
    # the smallest study whose top share holds the minimum PED-ANOVA's documentation asks
    enough = next(n for n in range(1, 1000) if math.ceil(TARGET_QUANTILE * n) >= MIN_TOP_TRIALS)
    assert importance_caveat(enough) == ""
    caveat = importance_caveat(enough - 1)
    assert f"PED-ANOVA wants {MIN_TOP_TRIALS} there ({enough} trials)" in caveat
    assert "a hint, not a finding" in importance_caveat(5)
