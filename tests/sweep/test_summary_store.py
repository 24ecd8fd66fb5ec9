"""Rows, stores and summaries on hand-made episode results (no simulation needed)."""

from __future__ import annotations

import json

import pytest

from puckboard.sweep.plan import EpisodeSpec, SweepPlan
from puckboard.sweep.rows import Outcome, error_row, result_row
from puckboard.sweep.run import SweepResult
from puckboard.sweep.store import CsvStore, open_store
from puckboard.sweep.summary import format_groups, format_ranking, rank_controllers


def fake_result(success: bool, failure: str | None, progress=(1.0, 0.5), collisions=(0, 1)):
    return {
        "scenario": "arena",
        "controller": "x",
        "seed": 0,
        "dt_s": 0.05,
        "steps": 100,
        "sim_time_s": 5.0,
        "wall_s": 0.1,
        "realtime_factor": 50.0,
        "success": success,
        "failure": failure,
        "robots": [
            {"name": n, "progress_laps": p, "distance_m": 1.0, "collisions": c}
            for n, p, c in zip(("a", "b"), progress, collisions)
        ],
        "events": [{"time_s": 1.0, "robot": "a", "kind": "collision"}],
    }


def rows_for(controller, params, outcomes):
    spec_params = tuple(sorted(params.items()))
    rows = []
    for seed, (success, failure) in enumerate(outcomes):
        spec = EpisodeSpec(controller, seed, spec_params)
        rows.append(result_row("arena", spec, fake_result(success, failure)))
    return rows


def test_row_flattens_robots_and_keeps_identity():
    spec = EpisodeSpec("stock", 3, (("noise.ground", 0.1),))
    row = result_row("arena", spec, fake_result(False, "collision"))
    assert row["key"] == spec.key("arena")
    assert row["controller"] == "stock" and row["seed"] == 3
    assert row["param.noise.ground"] == 0.1
    assert json.loads(row["params"]) == {"noise.ground": 0.1}
    assert row["progress_laps"] == pytest.approx(0.75)
    assert row["collisions"] == 1
    assert row["robot.b.collisions"] == 1
    assert json.loads(row["events"])[0]["kind"] == "collision"
    assert row["failure"] == "collision" and row["success"] is False


def test_error_rows_count_as_named_failures():
    spec = EpisodeSpec("broken.py:make_controller", 0)
    row = error_row("arena", spec, RuntimeError("boom"))
    outcome = Outcome.from_row(row)
    assert outcome.failure == "error" and not outcome.success
    assert "RuntimeError: boom" in row["error"]


def test_csv_store_appends_resumes_and_widens_columns(tmp_path):
    path = tmp_path / "runs.csv"
    first = rows_for("stock", {"dt": 0.05}, [(True, None), (False, "stuck")])
    with open_store(path) as store:
        store.append(first)
    reopened = open_store(path)
    assert isinstance(reopened, CsvStore)
    assert reopened.keys() == {r["key"] for r in first}
    later = rows_for("stock", {"dt": 0.05, "noise.ground": 0.2}, [(True, None)])
    reopened.append(later)
    rows = open_store(path).rows()
    assert len(rows) == 3
    assert rows[0]["param.noise.ground"] == ""
    assert rows[2]["param.noise.ground"] == "0.2"
    back = [Outcome.from_row(r) for r in rows]
    assert [o.success for o in back] == [True, False, True]
    assert back[1].failure == "stuck"
    assert back[2].params == (("dt", 0.05), ("noise.ground", 0.2))


def test_parquet_store_round_trips(tmp_path):
    pytest.importorskip("pyarrow")
    path = tmp_path / "runs.parquet"
    rows = rows_for("improved", {"layer.Cruise.speed": 2}, [(True, None), (False, "collision")])
    rows[1]["failure_detail"] = "only in one row"
    with open_store(path) as store:
        store.append(rows)
    back = open_store(path).rows()
    assert [r["key"] for r in back] == [r["key"] for r in rows]
    assert back[0]["success"] is True
    assert back[0]["failure_detail"] is None
    assert Outcome.from_row(back[1]).failure == "collision"


def test_unknown_extensions_and_foreign_files_are_refused(tmp_path):
    with pytest.raises(ValueError, match=r"\.csv or \.parquet"):
        open_store(tmp_path / "runs.xlsx")
    other = tmp_path / "other.csv"
    other.write_text("a,b\n1,2\n")
    with pytest.raises(ValueError, match="not a sweep results file"):
        open_store(other)


def test_summary_json_has_groups_with_counts_intervals_and_failures():
    plan = SweepPlan.from_specs(
        "arena", controllers=["stock", "improved"], seeds="0:10", sets=["dt=0.05,0.1"]
    )
    rows = (
        rows_for("stock", {"dt": 0.05}, [(True, None)] * 7 + [(False, "collision")] * 3)
        + rows_for("stock", {"dt": 0.1}, [(False, "stuck")] * 10)
        + rows_for("improved", {"dt": 0.05}, [(True, None)] * 10)
        + rows_for("improved", {"dt": 0.1}, [(True, None)] * 9 + [(False, "lost_line")])
    )
    result = SweepResult(plan=plan, outcomes=[Outcome.from_row(r) for r in rows], ran=len(rows))
    summary = json.loads(json.dumps(result.to_dict()))
    assert summary["episodes"] == 40
    groups = summary["groups"]
    assert [(g["controller"], g["params"]) for g in groups] == [
        ("stock", {"dt": 0.05}),
        ("stock", {"dt": 0.1}),
        ("improved", {"dt": 0.05}),
        ("improved", {"dt": 0.1}),
    ]
    first = groups[0]
    assert (first["episodes"], first["successes"]) == (10, 7)
    assert first["success_rate"] == pytest.approx(0.7)
    assert first["ci95_low"] == pytest.approx(0.39677, abs=1e-4)
    assert first["ci95_high"] == pytest.approx(0.89221, abs=1e-4)
    assert first["failures"] == {"collision": 3}
    assert groups[1]["failures"] == {"stuck": 10}
    assert groups[1]["ci95_low"] == 0.0
    assert first["mean_progress_laps"] == pytest.approx(0.75)
    assert first["mean_collisions"] == pytest.approx(1.0)
    ranking = summary["ranking"]
    assert [r["controller"] for r in ranking] == ["improved", "stock"]
    assert ranking[0]["successes"] == 19 and ranking[1]["successes"] == 7
    table = format_groups(result.groups())
    assert "collision 3" in table and "dt=0.1" in table
    assert format_ranking(rank_controllers(result.outcomes)).splitlines()[2].split()[:2] == [
        "1",
        "improved",
    ]


def test_csv_store_ignores_a_row_cut_off_by_a_killed_run(tmp_path):
    path = tmp_path / "runs.csv"
    rows = rows_for("stock", {}, [(True, None), (False, "stuck")])
    with open_store(path) as store:
        store.append(rows)
    text = path.read_text(encoding="utf-8")
    path.write_text(text[: text.rindex(rows[1]["key"].replace('"', '""')) + 40], encoding="utf-8")
    store = open_store(path)
    assert [r["key"] for r in store.rows()] == [rows[0]["key"]]
    assert path.read_text(encoding="utf-8").endswith("\n")
    later = rows_for("improved", {}, [(True, None)])
    later[0]["error"] = "Traceback\nline two"
    store.append(later)
    assert [r["key"] for r in open_store(path).rows()] == [rows[0]["key"], later[0]["key"]]


def test_tables_name_controller_files_by_their_file():
    from puckboard.sweep.summary import controller_labels

    labels = controller_labels(
        [
            "stock",
            "submissions/alice.py:make_controller",
            "submissions/bob.py:fast",
            "a/carol.py:make_controller",
            "b/carol.py:make_controller",
            "mypkg.ctrl:make",
        ]
    )
    assert labels["stock"] == "stock"
    assert labels["submissions/alice.py:make_controller"] == "alice"
    assert labels["submissions/bob.py:fast"] == "bob:fast"
    # two files called carol.py stay distinguishable
    assert labels["a/carol.py:make_controller"] == "a/carol.py:make_controller"
    assert labels["b/carol.py:make_controller"] == "b/carol.py:make_controller"
    assert labels["mypkg.ctrl:make"] == "mypkg.ctrl:make"
