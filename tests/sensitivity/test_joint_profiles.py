"""The joint method's rows of profile files: a file setting one number is a profile like
any other, and only a one-at-a-time value point, marked as such, is left out."""

from __future__ import annotations

import json

from sweep_helpers import DURATION

from puckboard.profile import load_profile_file
from puckboard.sensitivity import sensitivity_plan
from puckboard.sensitivity.joint import analyse_rows, joint_plan, run_joint
from puckboard.sensitivity.one_at_a_time.plan import FIELD_LABEL
from puckboard.sweep import InlineExecutor
from puckboard.sweep.options import RunOptions


def _rows(params: dict, n: int = 12) -> list[dict]:
    values = {"body_radius": 0.036, "ir_gain": 1.0}
    return [
        {
            "key": f"k{json.dumps(params, sort_keys=True)}{s}",
            "scenario": "two-robot-pass",
            "controller": "robust",
            "seed": s,
            "params": json.dumps(params, sort_keys=True),
            "success": s % 2 == 0,
            "failure": "" if s % 2 == 0 else "collision",
            "progress_laps": 0.5,
            "robot.left.profile_values": json.dumps({**values, "ir_gain": 0.9 + s / 100}),
        }
        for s in range(n)
    ]


def test_a_profile_file_setting_one_number_keeps_its_rows():
    one = {"robot.profile": "epuck", "profile.body_radius": 0.036, "variation": "plausible"}
    (a,) = analyse_rows(_rows(one), bins=2)
    assert a.band.episodes == 12
    assert a.profile == "epuck with body_radius set"  # the rows alone carry no file name


def test_a_one_at_a_time_value_point_is_left_out_by_its_mark_not_its_keys():
    plain = {"robot.profile": "epuck", "variation": "plausible"}
    point = {**plain, "profile.body_radius": 0.036, FIELD_LABEL: "body_radius"}
    two = {**plain, "profile.body_radius": 0.036, "profile.ir_gain": 1.0}
    analyses = analyse_rows([*_rows(plain), *_rows(point), *_rows(two)], bins=2)
    assert [(a.profile, a.band.episodes) for a in analyses] == [
        ("epuck", 12),
        ("epuck with body_radius, ir_gain set", 12),
    ]


def test_one_at_a_time_marks_only_the_value_points_that_draw_the_rest():
    def marks(variation: str) -> set:
        plan = sensitivity_plan("two-robot-pass", profiles=["epuck"], controllers=["stock"],
                                seeds=range(2), fields=["body_radius"], values=2,
                                variation=variation)  # fmt: skip
        return {(p.kind, p.params.get(FIELD_LABEL)) for p in plan.points}

    assert marks("plausible") == {("shipped", None), ("plausible", None), ("value", "body_radius")}
    assert marks("none") == {("shipped", None), ("plausible", None), ("value", None)}


def test_a_live_joint_run_on_a_one_number_file_analyses_it_under_the_files_name(
    short_scene, tmp_path
):
    path = tmp_path / "one.toml"
    path.write_text('base = "epuck"\nname = "one"\n[set]\nbody_radius = 0.036\n')
    one = load_profile_file(path)
    plan = joint_plan(short_scene.name, profiles=[one], controllers=["stock"], seeds=range(4),
                      fixed={"duration": DURATION}, bins=2)  # fmt: skip
    result = run_joint(plan, short_scene, RunOptions(executor=InlineExecutor()))
    (analysis,) = result.analyses
    assert analysis.band.episodes == 4
    assert analysis.profile == "one"
    assert result.to_dict()["episodes"] == 4


def test_a_labelled_point_runs_and_its_rows_carry_the_label(short_scene):
    """The label is part of the episode's identity, never given to the episode."""
    from puckboard.sensitivity import run_sensitivity

    plan = sensitivity_plan(short_scene.name, profiles=["epuck"], controllers=["stock"],
                            seeds=range(1), fields=["ir_gain"], values=2,
                            fixed={"duration": DURATION}, variation="plausible")  # fmt: skip
    result = run_sensitivity(plan, short_scene, RunOptions(executor=InlineExecutor()))
    assert result.sweep.errors == []
    labelled = [r for r in result.sweep.rows if FIELD_LABEL in json.loads(r["params"])]
    assert len(labelled) == 2 and all(r[f"param.{FIELD_LABEL}"] == "ir_gain" for r in labelled)
    (analysis,) = result.analyses
    assert [len(f.values) for f in analysis.fields] == [2]
