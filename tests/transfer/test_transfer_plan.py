"""What a transfer report runs (its points and sweeps) and how counts become cells."""

from __future__ import annotations

import dataclasses

import pytest

from puckboard.scenario.scenefile import load_scene
from puckboard.sweep import PlanError
from puckboard.sweep.rows import Outcome
from puckboard.transfer import DESIGN, FAMILIES, Family, choose_families, transfer_plan
from puckboard.transfer.families import NOISE_SETTINGS
from puckboard.transfer.result import analyse

PASS = load_scene("two-robot-pass")
BEND = load_scene("two-robot-pass-bend")
(NOISE,) = [f for f in FAMILIES if f.name == "noise"]


def plan_for(scenes=(PASS,), profiles=("epuck",), families=(NOISE,), **kwargs):
    return transfer_plan(
        list(scenes),
        controllers=kwargs.pop("controllers", ["robust"]),
        profiles={s.name: list(profiles) for s in scenes},
        seeds=kwargs.pop("seeds", range(400, 403)),
        families=list(families),
        **kwargs,
    )


def test_the_design_model_is_the_scene_with_plausible_robots():
    plan = plan_for()
    (design,) = [p for p in plan.points if p.family == DESIGN]
    assert dict(design.params) == {"robot.profile": "epuck", "variation": "plausible"}
    assert (design.scene, design.runs_on, design.scale) == ("two-robot-pass",) * 2 + (1.0,)


def test_noise_scales_every_noise_level_the_scene_sets():
    """two-robot-pass: wheels 3 %, IR 5 %, ground 0.03; no gyro noise to scale."""
    plan = plan_for()
    by_scale = {p.scale: dict(p.params) for p in plan.points if p.family == "noise"}
    assert sorted(by_scale) == [1.0, 2.0, 3.0]
    for scale in (2.0, 3.0):
        assert by_scale[scale] == {
            "robot.profile": "epuck",
            "variation": "plausible",
            "noise.wheel_speed": pytest.approx(0.03 * scale),
            "noise.proximity": pytest.approx(0.05 * scale),
            "noise.ground": pytest.approx(0.03 * scale),
        }
    assert "noise.gyro" in NOISE_SETTINGS and PASS.noise.gyro == 0


def test_scale_one_is_the_design_model_s_own_episodes():
    """The grid's ×1 and the design band are one set of episodes, as are the ×2 band and
    the grid's ×2: 3 sets, not 5."""
    plan = plan_for()
    (sweep,) = plan.sweeps
    assert len(sweep.points) == 3
    assert len(plan) == 3 * 3
    keys = {p.family: plan.point_key(p) for p in plan.points if p.scale == 1}
    assert keys["noise"] == keys[DESIGN]


def test_each_scene_and_profile_gets_its_points_and_each_scene_its_sweep():
    plan = plan_for(scenes=(PASS, BEND), profiles=("epuck", "epuck-vrep"))
    assert [s.scenario for s in plan.sweeps] == ["two-robot-pass", "two-robot-pass-bend"]
    assert all(len(s.points) == 2 * 3 for s in plan.sweeps)
    assert plan.profiles == {s: ("epuck", "epuck-vrep") for s in plan.scenes}
    cells = analyse(plan, {})
    assert [(c.scene, c.profile) for c in cells] == [
        (s, p) for s in plan.scenes for p in ("epuck", "epuck-vrep")
    ]


def test_a_replacement_scene_runs_once_for_every_scene_it_replaces():
    """A family that swaps the scene (as a generated track does) is one sweep on that
    scene, shared by the report's scenes: the same episodes, listed in each block."""
    other = load_scene("line-follow")
    swapped = Family(name="other-track", what="another track", scene=other.name)
    plan = plan_for(scenes=(PASS, BEND), families=(swapped,), replacements={other.name: other})
    assert sorted(s.scenario for s in plan.sweeps) == [
        "line-follow", "two-robot-pass", "two-robot-pass-bend"
    ]  # fmt: skip
    assert len(plan.sweep_for("line-follow").points) == 1
    runs_on = {(p.scene, p.family): p.runs_on for p in plan.points}
    assert runs_on[("two-robot-pass-bend", "other-track")] == "line-follow"


def test_a_family_s_sets_and_variation_are_its_points_parameters():
    family = Family(name="exact", what="robots as profiled", sets={"noise.ground": 0.1},
                    variation="none")  # fmt: skip
    plan = plan_for(families=(family,))
    (point,) = [p for p in plan.points if p.family == "exact"]
    assert dict(point.params) == {
        "robot.profile": "epuck",
        "variation": "none",
        "noise.ground": 0.1,
    }


def test_a_scene_without_noise_skips_the_noise_family_and_says_why():
    quiet = dataclasses.replace(PASS, noise=dataclasses.replace(PASS.noise, wheel_speed=0.0,
                                proximity=0.0, ground=0.0))  # fmt: skip
    plan = plan_for(scenes=(quiet,))
    assert [p.family for p in plan.points] == [DESIGN]
    (skipped,) = plan.skipped
    assert skipped.family == "noise" and "nothing to scale" in skipped.why


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"scenes": ()}, "at least one scene"),
        ({"scenes": (PASS, PASS)}, "scene listed twice"),
        ({"profiles": ("epuck", "epuck")}, "profile listed twice"),
        ({"families": (Family(name="x", what="x", scene="nowhere"),)}, "scene nowhere is not"),
    ],
)
def test_bad_plans_are_one_line(kwargs, message):
    with pytest.raises(PlanError, match=message):
        plan_for(**kwargs)


def test_families_are_chosen_by_name_and_a_wrong_name_lists_them():
    assert choose_families(None) == FAMILIES
    assert choose_families(["noise"]) == (NOISE,)
    with pytest.raises(
        ValueError, match=r"no family 'nois' \(did you mean 'noise'\?\); families: noise"
    ):
        choose_families(["nois"])
    with pytest.raises(ValueError, match="listed twice"):
        choose_families(["noise", "noise"])


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"grid": (1.0, 2.0)}, "a grid needs scaled, stepped or valued settings"),
        ({"scaled": ("noise.ground",), "grid": (2.0, 1.0), "scale": 2.0}, "starts at 1"),
        ({"valued": ("surface.line_contrast",), "grid": (1.0, 0.5, 0.75)}, "moves outward"),
        ({"stepped": ("control.latency",), "grid": (0.0, 2.0, 1.0), "origin": 0.0}, "outward"),
        ({"scaled": ("noise.ground",), "stepped": ("control.latency",)}, "not two"),
        ({"scaled": ("noise.ground",), "grid": (1.0, 3.0), "scale": 2.0}, "not on its grid"),
    ],
)
def test_a_family_s_grid_is_declared_outward_from_the_design_model(kwargs, message):
    with pytest.raises(ValueError, match=message):
        Family(name="f", what="f", **kwargs)


def outcomes(plan, wins_by_scale, seeds=4):
    """Outcomes of every point of ``plan`` (one scene, one profile, one controller):
    ``wins_by_scale[scale]`` of ``seeds`` episodes pass."""
    (sweep,) = plan.sweeps
    out = []
    for point in plan.points:
        if point.family == DESIGN:
            continue
        for seed in range(seeds):
            params = tuple(sorted({**plan.fixed, **point.params}.items()))
            out.append(
                Outcome(
                    key=f"{point.scale}/{seed}", controller="robust", params=params, seed=seed,
                    success=seed < wins_by_scale[point.scale], failure="collision",
                    progress_laps=1.0, collisions=0.0,
                )
            )  # fmt: skip
    return {sweep.scenario: out}


def test_a_cell_has_the_design_band_each_family_s_band_and_its_radius():
    plan = plan_for(seeds=range(4))
    (cell,) = analyse(plan, outcomes(plan, {1.0: 4, 2.0: 4, 3.0: 2}))
    assert (cell.design.stats.successes, cell.design.stats.episodes) == (4, 4)
    (band,) = cell.families
    assert (band.label, band.stats.successes) == ("noise ×2", 4)
    (radius,) = cell.radii
    assert [(p.scale, p.successes) for p in radius.grid] == [(1, 4), (2, 4), (3, 2)]
    assert radius.shown == ("×1", "×2", "×3")
    assert (radius.estimate.radius, radius.estimate.beyond.scale) == (2.0, 3.0)
    assert radius.lower.radius is None  # 4 of 4: lower bound 0.51
    data = cell.to_dict()
    assert data["radii"][0]["at"]["ci95_low"] == pytest.approx(4 / (4 + 1.959963984540054**2))
    assert data["families"][0]["stats"]["failures"] == {}


def test_a_point_not_run_is_not_run_in_its_cell():
    plan = plan_for(seeds=range(4))
    partial = {k: [o for o in v if not o.key.startswith("2.0/")] for k, v in
               outcomes(plan, {1.0: 4, 2.0: 4, 3.0: 4}).items()}  # fmt: skip
    (cell,) = analyse(plan, partial)
    assert cell.families[0].stats is None
    (radius,) = cell.radii
    assert radius.grid[1].episodes == 0
    assert (radius.estimate.radius, radius.estimate.complete) == (1.0, False)


# -- the control loop's timing ------------------------------------------------------------
def by_family(plan, name):
    return {p.scale: dict(p.params) for p in plan.points if p.family == name}


def test_a_link_runs_at_its_slow_end_in_whole_steps():
    """epuck2-wifi: period up to 100 ms, latency up to 40 ms (puckboard.profile.links);
    at the pass scene's 50 ms step: 2 steps, and 0.8 steps rounded to 1."""
    plan = plan_for(families=choose_families(["link epuck2-wifi"]))
    assert by_family(plan, "link epuck2-wifi") == {
        1.0: {"robot.profile": "epuck", "variation": "plausible",
              "control.period": pytest.approx(0.1), "control.latency": pytest.approx(0.05)},
    }  # fmt: skip
    (band,) = analyse(plan, {})[0].families
    assert band.what.startswith("period 100 ms, latency 50 ms: ")


def test_a_link_no_slower_than_the_design_loop_is_not_run_and_says_why():
    """usb-sercom's slow end (50 ms, 10 ms) is one step and no delay at a 50 ms step."""
    plan = plan_for(families=choose_families(["link usb-sercom"]))
    assert [p.family for p in plan.points] == [DESIGN]
    (skipped,) = plan.skipped
    assert "50 ms step its slow end is the design loop" in skipped.why


def test_links_with_the_same_timing_in_whole_steps_share_their_episodes():
    plan = plan_for(families=choose_families(["link epuck2-wifi", "link bluetooth-sercom"]))
    (sweep,) = plan.sweeps
    assert len(sweep.points) == 2  # the design model and the one 100 ms / 50 ms loop


@pytest.mark.parametrize(
    ("family", "name"),
    [("link epuck2-wifi", "control.latency"), ("noise", "noise.ground"),
     ("reality-gap", "variation"), ("obstacle reflectance", "obstacle.ir_reflectance")],
)  # fmt: skip
def test_a_fixed_value_a_family_decides_is_refused(family, name):
    """A fixed value would be overridden at the family's models."""
    with pytest.raises(PlanError, match=f"--set {name}: the family '{family}' decides it"):
        plan_for(families=choose_families([family]), fixed={name: 0.1})


@pytest.mark.parametrize(
    ("family", "dt", "models"),
    [
        ("latency", 0.01, {1.0: {"control.latency": 0.01}, 2.0: {"control.latency": 0.02}}),
        ("period", 0.02, {2.0: {"control.period": 0.04}, 4.0: {"control.period": 0.08}}),
        ("link usb-sercom", 0.01, {1.0: {"control.period": 0.05, "control.latency": 0.01}}),
    ],
)
def test_a_fixed_dt_is_the_step_whole_steps_count_in(family, dt, models):
    """A link judged at a finer physics step: the family's models are counted in the
    fixed ``dt`` (the usb link's slow end is its own at 10 ms, not the design loop)."""
    plan = plan_for(families=choose_families([family]), fixed={"dt": dt})
    base = {"robot.profile": "epuck", "variation": "plausible"}
    got = {k: v for k, v in by_family(plan, family).items() if k in models}
    assert got == {
        k: {**base, **{n: pytest.approx(x) for n, x in v.items()}} for k, v in models.items()
    }
    assert plan.dts == {"two-robot-pass": dt}


def test_fixed_values_are_every_model_s_base():
    fixed = {"layer.ClearanceGuard.clearance": 0.5}
    plan = plan_for(families=choose_families(["link epuck2-wifi", "latency"]), fixed=fixed)
    assert [dict(sweep.fixed) for sweep in plan.sweeps] == [fixed]
    assert len(plan.sweeps[0].points) == 4  # design, the link, latency 50 and 100 ms
    assert not any(set(fixed) & set(p.params) for p in plan.points)  # none overrides it


def test_period_and_latency_grids_are_whole_steps_from_the_design_loop():
    plan = plan_for(families=choose_families(["period", "latency"]))
    base = {"robot.profile": "epuck", "variation": "plausible"}
    period, latency = by_family(plan, "period"), by_family(plan, "latency")
    assert period == {
        1.0: base,
        2.0: {**base, "control.period": pytest.approx(0.1)},
        4.0: {**base, "control.period": pytest.approx(0.2)},
    }
    assert latency == {
        0.0: base,
        1.0: {**base, "control.latency": pytest.approx(0.05)},
        2.0: {**base, "control.latency": pytest.approx(0.1)},
    }
    cell = analyse(plan, {})[0]
    assert cell.families == ()  # a radius only: no band of its own
    assert [r.shown for r in cell.radii] == [
        ("50 ms", "100 ms", "200 ms"),
        ("0 ms", "50 ms", "100 ms"),
    ]


# -- surfaces and conditions -----------------------------------------------------------------
def test_surface_grids_set_the_value_itself_from_the_scene_s_own_outward():
    plan = plan_for(families=choose_families(["line contrast", "obstacle reflectance"]))
    base = {"robot.profile": "epuck", "variation": "plausible"}
    assert by_family(plan, "line contrast") == {
        1.0: base,
        0.75: {**base, "surface.line_contrast": 0.75},
        0.5: {**base, "surface.line_contrast": 0.5},
    }
    assert by_family(plan, "obstacle reflectance")[0.1] == {**base, "obstacle.ir_reflectance": 0.1}
    cell = analyse(plan, {})[0]
    assert [b.label for b in cell.families] == ["line contrast 0.5", "obstacle reflectance 0.1"]
    assert [r.shown for r in cell.radii] == [("1", "0.75", "0.5"), ("1", "0.55", "0.1")]


def test_a_scene_whose_own_value_is_not_the_grid_s_origin_says_so():
    grey = dataclasses.replace(PASS, track=dataclasses.replace(PASS.track, contrast=0.8))
    plan = plan_for(scenes=(grey,), families=choose_families(["line contrast"]))
    (skipped,) = plan.skipped
    assert "own surface.line_contrast is 0.8, not the grid's origin 1" in skipped.why


def test_reality_gap_is_a_variation_of_its_own():
    plan = plan_for(families=choose_families(["reality-gap"]))
    assert by_family(plan, "reality-gap") == {
        1.0: {"robot.profile": "epuck", "variation": "reality-gap"}
    }


# -- the text report ---------------------------------------------------------------------------
def test_the_report_has_a_column_per_controller_a_row_per_model_and_a_legend():
    from puckboard.sweep.run import SweepResult
    from puckboard.transfer import TransferResult, format_result

    plan = plan_for(seeds=range(4))
    (sweep,) = plan.sweeps
    (rows,) = outcomes(plan, {1.0: 4, 2.0: 4, 3.0: 2}).values()
    result = TransferResult.of(plan, [SweepResult(plan=sweep, outcomes=rows, ran=len(rows))], 2.0)
    text = format_result(result)
    lines = text.splitlines()
    assert lines[0].startswith("transfer: 12 of 12 episodes (12 run), 2.0 s, 6.0 episodes/s")
    header = lines[lines.index("two-robot-pass · epuck") + 1]
    assert header.split() == ["model", "robust"]
    assert any(line.split()[:3] == ["noise", "×2", "4/4"] for line in lines)
    (radius,) = [line for line in lines if line.startswith("radius: noise ")]
    assert radius.split("  ")[-1].strip() == "×2: 4/4 [51, 100] %; ×3 2/4"
    assert "  radius: noise: grid ×1, ×2, ×3; " in text
    assert "at least 73 seeds" in lines[-1]


def test_a_family_that_runs_the_report_s_own_scene_is_the_design_model_and_says_so():
    generated = load_scene("generated-pass")
    plan = plan_for(scenes=(generated,), families=choose_families(["generated-pass", "noise"]))
    assert "generated-pass" not in {p.family for p in plan.points}
    (skipped,) = [s for s in plan.skipped if s.family == "generated-pass"]
    assert skipped.why == "it is the design model here: generated-pass is the scene it runs"


def test_an_interrupted_report_marks_what_ran_short_incomplete():
    """A point that ran one of its two seeds reads "incomplete", and a radius does not
    walk on through it (the rows once mixed 2/2 and 1/1 and read "≥ ×3: 2/2")."""
    from puckboard.sweep.run import SweepResult
    from puckboard.transfer import format_result
    from puckboard.transfer.result import TransferResult

    plan = plan_for(seeds=range(4))
    ran = {k: [o for o in v if not (o.key.startswith("3.0/") and o.seed >= 2)]
           for k, v in outcomes(plan, {1.0: 4, 2.0: 4, 3.0: 4}).items()}  # fmt: skip
    (sweep,) = plan.sweeps
    result = TransferResult(plan, [SweepResult(plan=sweep, outcomes=ran[sweep.scenario])])
    result.cells = analyse(plan, ran)
    result.stopped = True
    (radius,) = result.cells[0].radii
    assert (radius.estimate.radius, radius.estimate.complete) == (2.0, False)
    text = format_result(result, stored="t.csv")
    assert "\nINCOMPLETE: the run was stopped; bands and radii marked incomplete ran fewer " in text
    assert "×2: 4/4 [51, 100] %; further not run (incomplete)" in text


def test_the_report_names_the_fixed_settings_in_its_head_and_each_model():
    """--set control.latency=0.05 with the period family once ran every row 50 ms late
    while the report said "no delay"."""
    from puckboard.sweep.run import SweepResult
    from puckboard.transfer import format_result
    from puckboard.transfer.result import TransferResult

    fixed = {"control.latency": 0.05, "layer.Cruise.speed": 3.0}
    plan = plan_for(families=choose_families(["period"]), fixed=fixed)
    result = TransferResult.of(plan, [SweepResult(plan=s, outcomes=[]) for s in plan.sweeps])
    head, *_ = text = format_result(result).splitlines()
    assert head.endswith("; every model with control.latency=0.05, layer.Cruise.speed=3.0")
    assert (
        "  design: the scene with plausible robots (--variation plausible); "
        "with control.latency=0.05" in text
    )
    assert (
        "  radius: period: grid 50 ms, 100 ms, 200 ms; the controller ticks every 1, 2 or 4 "
        "physics steps; with control.latency=0.05" in text
    )
