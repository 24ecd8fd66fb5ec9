"""``puckboard sensitivity`` from the command line: results, the figure, resuming, mistakes."""

from __future__ import annotations

import json

import pytest

from puckboard.cli import main
from puckboard.scenario import load_scene, scene_to_dict

#: A few seconds of line following: enough for the command's whole path, quick.
SMALL = [
    "sensitivity", "line-follow", "--controller", "stock", "--profile", "epuck",
    "--fields", "ir_gain,prox_radius.side", "--values", "2", "--seeds", "0:2",
    "--duration", "3", "--workers", "1", "--quiet",
]  # fmt: skip


def one_error_line(capsys) -> str:
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1, lines
    assert lines[0].startswith("puckboard sensitivity: error: ")
    return lines[0]


def test_json_gives_every_field_and_value_a_rate_with_its_interval(capsys):
    assert main([*SMALL, "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    # shipped, plausible, and two values of each field (ir_gain 0.7 and 1.3; 30 and 33 mm)
    assert data["planned"] == data["episodes"] == data["ran"] == 6 * 2
    assert data["episodes_per_s"] > 0
    (analysis,) = data["analyses"]
    assert (analysis["controller"], analysis["profile"]) == ("stock", "epuck")
    assert {f["field"] for f in analysis["fields"]} == {"ir_gain", "prox_radius.side"}
    for f in analysis["fields"]:
        assert [v["value"] for v in f["values"] if not v["shipped"]] == [f["low"], f["high"]]
        assert [v["value"] for v in f["values"] if v["shipped"]] == [f["shipped_value"]]
        for v in f["values"]:
            assert v["episodes"] == 2
            assert 0.0 <= v["ci95_low"] <= v["success_rate"] <= v["ci95_high"] <= 1.0
    assert analysis["shipped"]["episodes"] == analysis["plausible"]["episodes"] == 2


def test_plot_draws_the_figure_and_out_resumes(capsys, tmp_path):
    pytest.importorskip("matplotlib")
    out, figure = tmp_path / "runs.csv", tmp_path / "sensitivity.png"
    assert main([*SMALL, "--out", str(out), "--plot", str(figure)]) == 0
    printed = capsys.readouterr().out
    assert printed.splitlines()[0].startswith(
        f"line-follow: 12 of 12 episodes (12 run, 0 already in {out}), "
    )
    assert printed.rstrip().endswith(f"plot written to {figure}")
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert main([*SMALL, "--out", str(out)]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first.startswith(f"line-follow: 12 of 12 episodes (0 run, 12 already in {out}), ")


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (
            ["--fields", "ir_gains"],
            "'ir_gains' is not an uncertain field of epuck (did you mean ir_gain?)",
        ),
        (["--fields", ","], "--fields: name at least one field"),
        (["--values", "0"], "--values must be at least 1, got 0"),
        (["--plot", "figure.txt"], "--plot 'figure.txt': use a .png, .svg or .pdf file name"),
        (["--profile", "epuck-3"], "unknown robot profile 'epuck-3'"),
        (["--seeds", "5:1"], "--seeds '5:1' is empty"),
        (["--controller", "nosuch"], "nosuch"),
    ],
)  # fmt: skip
def test_mistakes_are_one_line_before_anything_runs(capsys, change, message):
    args = list(SMALL)
    flag, value = change
    if flag in args:
        args[args.index(flag) + 1] = value
    else:
        args += [flag, value]
    assert main(args) == 2
    assert message in one_error_line(capsys)


def test_robots_of_different_profiles_need_a_profile_named(capsys, tmp_path):
    data = scene_to_dict(load_scene("two-robot-pass"))
    data["robots"][0]["profile"] = "epuck"
    scene = tmp_path / "mixed.json"
    scene.write_text(json.dumps(data), encoding="utf-8")
    assert main(["sensitivity", str(scene), "--seeds", "0:1", "--workers", "1"]) == 2
    assert "have different profiles; name the one to analyse with --profile" in one_error_line(
        capsys
    )


def test_without_a_profile_the_scene_s_own_is_analysed(capsys):
    """two-robot-pass's robots are V-REP's model, whose one uncertain number is its body."""
    args = [
        "sensitivity", "two-robot-pass", "--controller", "improved", "--values", "2",
        "--seeds", "0:1", "--duration", "2", "--workers", "1", "--quiet", "--json",
    ]  # fmt: skip
    assert main(args) == 0
    (analysis,) = json.loads(capsys.readouterr().out)["analyses"]
    assert analysis["profile"] == "epuck-vrep"
    assert [f["field"] for f in analysis["fields"]] == ["body_radius"]


def test_the_command_is_listed(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    assert "sensitivity" in capsys.readouterr().out


def test_progress_names_the_command(capsys):
    """Without --quiet, progress goes to stderr (plain lines when it is not a terminal)
    under the command's own name, and the result stays on stdout."""
    args = [a for a in SMALL if a != "--quiet"]
    assert main([*args, "--json"]) == 0
    captured = capsys.readouterr()
    progress = captured.err.strip().splitlines()
    assert progress and all(line.startswith("sensitivity: ") for line in progress), progress
    assert progress[-1].startswith("sensitivity: 12/12 episodes (100 %)"), progress
    json.loads(captured.out)


#: The joint method on a few plausible robots: the command's whole path, quick.
JOINT = [
    "sensitivity", "line-follow", "--controller", "stock", "--profile", "epuck",
    "--method", "joint", "--seeds", "0:8", "--bins", "2", "--duration", "2",
    "--workers", "1", "--quiet",
]  # fmt: skip


def test_joint_reports_the_band_every_curve_and_from_recomputes_it(capsys, tmp_path):
    out = tmp_path / "joint.csv"
    assert main([*JOINT, "--out", str(out), "--json"]) == 0
    live = json.loads(capsys.readouterr().out)
    assert (live["method"], live["ran"], live["episodes"]) == ("joint", 8, 8)
    (analysis,) = live["analyses"]
    assert analysis["band"]["episodes"] == 8
    assert analysis["numbers"], "every drawn number has its curve"
    for number in analysis["numbers"]:
        assert sum(b["episodes"] for b in number["bins"]) == 8
        assert all(b["rate_low"] <= b["rate"] <= b["rate_high"] for b in number["bins"])
    # the same report from the file, without running an episode
    assert main(["sensitivity", "--from", str(out), "--bins", "2", "--json"]) == 0
    again = json.loads(capsys.readouterr().out)
    assert "ran" not in again
    assert again["analyses"] == live["analyses"]
    assert (again["scenario"], again["seeds"]) == ("line-follow", "0:8")
    # the same command resumes from the file: nothing runs again; the figure is drawn
    figure = tmp_path / "joint.png"
    assert main([*JOINT, "--out", str(out), "--plot", str(figure)]) == 0
    printed = capsys.readouterr().out
    assert "(0 run, 8 already in" in printed
    assert printed.rstrip().endswith(f"plot written to {figure}")
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--bins", "1"], "--bins must be at least 2, got 1"),
        (["--seeds", "0:3"], "too few for 2 bins"),
        (["--fields", "ir_gain"], "--fields is for --method one-at-a-time"),
    ],
)  # fmt: skip
def test_joint_mistakes_are_one_line(capsys, args, message):
    changed = list(JOINT)
    if args[0] in changed:
        changed[changed.index(args[0]) + 1] = args[1]
    else:
        changed += args
    assert main(changed) == 2
    assert message in one_error_line(capsys)


def test_from_a_file_that_cannot_be_read_is_one_line(capsys, tmp_path):
    missing = tmp_path / "missing.csv"
    assert main(["sensitivity", "--from", str(missing)]) == 2
    assert f"--from '{missing}': no such file" in one_error_line(capsys)
    bad = tmp_path / "notes.txt"
    bad.write_text("x", encoding="utf-8")
    assert main(["sensitivity", "--from", str(bad)]) == 2
    assert "use a .csv or .parquet file name" in one_error_line(capsys)
    assert main(["sensitivity", "--from", str(missing), "--method", "one-at-a-time"]) == 2
    assert "--from recomputes a joint analysis" in one_error_line(capsys)


def test_joint_without_statsmodels_names_the_analysis_extra(monkeypatch, capsys, tmp_path):
    import sys

    monkeypatch.setitem(sys.modules, "statsmodels", None)  # as if it were not installed
    assert main(JOINT) == 2
    assert "pip install 'puckboard[analysis]'" in one_error_line(capsys)
    assert main(["sensitivity", "--from", str(tmp_path / "runs.csv")]) == 2
    assert "pip install 'puckboard[analysis]'" in one_error_line(capsys)


def _plausible_rows(path, n: int) -> None:
    """``n`` rows of plausible robots, as a joint run writes them, in ``path``."""
    from puckboard.sweep import open_store

    rows = [
        {
            "key": f"k{s}", "scenario": "line-follow", "controller": "stock", "seed": s,
            "params": json.dumps({"robot.profile": "epuck", "variation": "plausible"}),
            "success": s % 2 == 0, "failure": "" if s % 2 == 0 else "lost_line",
            "progress_laps": 0.5,
            "robot.left.profile_values": json.dumps({"ir_gain": 0.9 + s / 100}),
        }
        for s in range(n)
    ]  # fmt: skip
    with open_store(path) as store:
        store.append(rows)


def test_from_refuses_more_bins_than_its_rows_fill_as_a_live_run_does(capsys, tmp_path):
    rows = tmp_path / "rows.csv"
    _plausible_rows(rows, 30)
    assert main(["sensitivity", "--from", str(rows), "--bins", "1000"]) == 2
    line = one_error_line(capsys)
    assert "the rows hold 30 episodes of stock on epuck, too few for 1000 bins" in line
    assert line.endswith("use --bins 15 or fewer")
    assert main(["sensitivity", "--from", str(rows), "--bins", "15", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["bins"] == 15


def test_from_a_file_of_another_kind_names_from_not_out(capsys, tmp_path):
    picture = tmp_path / "pic.png"
    picture.write_bytes(b"\x89PNG")
    assert main(["sensitivity", "--from", str(picture)]) == 2
    line = one_error_line(capsys)
    assert line == (
        f"puckboard sensitivity: error: --from '{picture}': use a .csv or .parquet file name "
        "(.parquet needs pyarrow: pip install 'puckboard[dask]')"
    )
    assert "--out" not in line


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--from", "ROWS", "--controller", "robust"], "--from analyses the rows 'ROWS' holds "
         "and runs no episode: drop --controller"),
        (["--from", "ROWS", "--seeds", "0:8"], "runs no episode: drop --seeds"),
        (["--from", "ROWS", "--seeds", "0:8", "--out", "OUT"], "drop --seeds, --out"),
        (["--from", "ROWS", "--set", "control.period=0.1"], "runs no episode: drop --set"),
        ([*JOINT[1:], "--values", "3"], "--values is for --method one-at-a-time; the joint "
         "method draws every number; its curves have --bins bins"),
        ([*JOINT[1:], "--variation", "none"], "--variation is for --method one-at-a-time; the "
         "joint method's robots are always plausible"),
        ([*SMALL[1:], "--method", "one-at-a-time", "--bins", "3"], "--bins is for --method "
         "joint and --from; one at a time, each field's curve has --values values"),
        ([*SMALL[1:], "--bins", "3"], "--bins is for --method joint and --from"),
    ],
)  # fmt: skip
def test_an_option_the_method_would_ignore_is_refused_in_one_line(capsys, tmp_path, args, message):
    rows, out = tmp_path / "rows.csv", tmp_path / "out.csv"
    _plausible_rows(rows, 8)
    args = [str(rows) if a == "ROWS" else str(out) if a == "OUT" else a for a in args]
    assert main(["sensitivity", *args]) == 2
    assert message.replace("ROWS", str(rows)) in one_error_line(capsys)
    assert not out.exists()


def test_too_many_values_are_refused_and_close_values_read_apart(capsys):
    from puckboard.sensitivity.units import value_digits

    values = SMALL.index("--values") + 1  # an option is given once
    assert main([*SMALL[:values], "100000", *SMALL[values + 1 :]]) == 2
    assert "--values 100000 is more than 100 per field" in one_error_line(capsys)
    values = [0.7 + i * 0.6 / 99 for i in range(100)]
    digits = value_digits(values)
    assert len({f"{v:.{digits}g}" for v in values}) == 100
    assert value_digits([10.0, 14.0, 17.0]) == 4  # few values keep the usual 4 digits


def test_a_field_with_no_spread_is_not_ranked(capsys):
    from puckboard.sensitivity.one_at_a_time.plan import Field
    from puckboard.sensitivity.one_at_a_time.report import format_analysis
    from puckboard.sensitivity.one_at_a_time.summary import Analysis, FieldResult, ValueResult
    from puckboard.sweep.summary import GroupSummary

    def stats(ok: int) -> GroupSummary:
        return GroupSummary.of("stock", {}, [_outcome(i < ok) for i in range(4)])

    def field(path: str, rates: list[int]) -> FieldResult:
        f = Field("epuck", path, "1", 0.7, 1.3, 1.0, (0.7, 1.3), "assumed", "assumed")
        return FieldResult(
            f, tuple(ValueResult(v, False, stats(ok)) for v, ok in zip(f.values, rates))
        )

    analysis = Analysis(
        "stock", "epuck", None, None, (field("ir_gain", [1, 3]), field("x", [2, 2]))
    )
    text = format_analysis(analysis, "stock", "0:4")
    ranked = [
        line.split()[:2] for line in text.splitlines() if line.strip().startswith(("1 ", "- "))
    ]
    assert ranked == [["1", "ir_gain"], ["-", "x"]]
    assert "- no spread: the same rate at every value, nothing to rank" in text


def _outcome(success: bool):
    from puckboard.sweep.rows import Outcome

    return Outcome("k", "stock", (), 0, success, "" if success else "lost_line", 0.5, 0.0)
