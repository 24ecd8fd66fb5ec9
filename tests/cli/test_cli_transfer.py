"""``puckboard transfer`` from the command line: the JSON, the figure, resuming, Ctrl-C
and mistakes, on a few seconds of line following."""

from __future__ import annotations

import csv
import dataclasses
import json

import pytest
from sweep_helpers import CountingExecutor

import puckboard.sweep
from puckboard.cli import main
from puckboard.profile.links import LINKS
from puckboard.sweep import InlineExecutor

#: Two seeds of two seconds: the command's whole path, quick. Three sets of episodes
#: (design = noise ×1, ×2, ×3) × 2 seeds.
SMALL = [
    "transfer", "line-follow", "--controller", "stock", "--profile", "epuck",
    "--families", "noise", "--seeds", "0:2", "--duration", "2", "--workers", "1", "--quiet",
]  # fmt: skip
EPISODES = 3 * 2


class InProcess(InlineExecutor):
    """The local executor's interface, its episodes run in this process: the command's
    whole path without a worker's start-up (one test below keeps the real workers)."""

    def __init__(self, workers: int | None = None) -> None:
        self.workers = 1

    def start(self) -> InProcess:
        return self


@pytest.fixture
def in_process(monkeypatch):
    monkeypatch.setattr(puckboard.sweep, "LocalExecutor", InProcess)


def one_error_line(capsys) -> str:
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1, lines
    assert lines[0].startswith("puckboard transfer: error: ")
    return lines[0]


def test_json_lists_the_design_band_the_families_and_the_radii(capsys):
    assert main([*SMALL, "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["planned"] == data["episodes"] == data["ran"] == EPISODES
    assert (data["seeds"], data["threshold"], data["radius_by"]) == ("0:2", 0.95, "estimate")
    assert [f["name"] for f in data["families"]] == ["noise"]
    (cell,) = data["cells"]
    assert (cell["scene"], cell["controller"], cell["profile"]) == ("line-follow", "stock", "epuck")
    bands = [cell["design"], *(b["stats"] for b in cell["families"])]
    for band in bands:
        assert band["episodes"] == 2
        assert 0.0 <= band["ci95_low"] <= band["success_rate"] <= band["ci95_high"] <= 1.0
    (radius,) = cell["radii"]
    assert [p["scale"] for p in radius["grid"]] == [1, 2, 3]
    assert radius["grid"][0]["successes"] == cell["design"]["successes"]
    assert radius["grid"][1]["successes"] == cell["families"][0]["stats"]["successes"]
    if radius["radius"] is not None:
        assert radius["at"]["scale"] == radius["radius"]


def test_every_family_is_listed_by_default_with_its_band_or_radius(capsys, in_process):
    """The pass scene, one seed of two seconds: every family of the report."""
    args = ["transfer", "two-robot-pass", "--controller", "robust", "--seeds", "400:401",
            "--duration", "2", "--quiet", "--json"]  # fmt: skip
    assert main(args) == 0
    data = json.loads(capsys.readouterr().out)
    (cell,) = data["cells"]
    assert cell["profile"] == "epuck-vrep"  # the scene's own
    links = [f["name"] for f in data["families"] if f["link"]]
    assert links == [f"link {n}" for n in LINKS if n != "coppeliasim-sync"]
    banded = [b["family"] for b in cell["families"]]
    skipped = [s["family"] for s in cell["not_applicable"]]
    held_out = ["noise", *links, "line contrast", "obstacle reflectance", "generated-pass",
                "reality-gap"]  # fmt: skip
    assert sorted(banded + skipped) == sorted(held_out)
    assert skipped == ["link usb-sercom"]
    assert [r["family"] for r in cell["radii"]] == [
        "noise", "period", "latency", "line contrast", "obstacle reflectance"
    ]  # fmt: skip
    for band in cell["families"]:
        assert band["stats"]["episodes"] == 1
    runs_on = {b["family"]: b["runs_on"] for b in cell["families"]}
    assert runs_on["generated-pass"] == "generated-pass"
    assert runs_on["reality-gap"] == "two-robot-pass"


def test_out_resumes_and_the_plot_is_written(capsys, tmp_path, in_process):
    pytest.importorskip("matplotlib")
    out, figure = tmp_path / "runs.csv", tmp_path / "transfer.png"
    assert main([*SMALL, "--out", str(out), "--plot", str(figure)]) == 0
    printed = capsys.readouterr().out
    assert printed.startswith(f"transfer: {EPISODES} of {EPISODES} episodes ({EPISODES} run, 0 ")
    assert "line-follow · epuck" in printed and "radius: noise" in printed
    assert printed.rstrip().endswith(f"plot written to {figure}")
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert main([*SMALL, "--out", str(out)]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first.startswith(f"transfer: {EPISODES} of {EPISODES} episodes (0 run, {EPISODES} ")


def test_set_is_every_model_s_base(capsys, tmp_path, in_process):
    """``--set`` (as a tuning's "use it" line gives it) reaches the design model and every
    family's, each family's own changes on top."""
    out = tmp_path / "runs.csv"
    assert main([*SMALL, "--set", "control.period=0.1", "--out", str(out), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["fixed"] == {"duration": 2.0, "control.period": 0.1}
    with out.open(newline="", encoding="utf-8") as handle:
        rows = [json.loads(row["params"]) for row in csv.DictReader(handle)]
    assert len(rows) == EPISODES
    assert all(params["control.period"] == 0.1 for params in rows)
    assert len({params.get("noise.proximity") for params in rows}) == 3  # the noise family's


def test_rows_carry_their_family_and_model_as_columns(capsys, tmp_path, in_process):
    out = tmp_path / "runs.csv"
    assert main([*SMALL, "--out", str(out)]) == 0
    with out.open(newline="", encoding="utf-8") as handle:
        labels = {(row["family"], row["model"]) for row in csv.DictReader(handle)}
    assert labels == {
        ("design; noise", "design; noise ×1"),
        ("noise", "noise ×2"),
        ("noise", "noise ×3"),
    }


def test_python_gives_the_report_the_command_prints(capsys, in_process):
    """The documented entry point (docs/transfer.md): names in, the command's result out."""
    from puckboard.sweep import RunOptions
    from puckboard.transfer import format_result, run_transfer

    result = run_transfer(
        "line-follow", controllers=["stock"], profiles=["epuck"], seeds="0:2",
        families=["noise"], fixed={"duration": 2.0}, options=RunOptions(executor=InProcess()),
    )  # fmt: skip
    assert main(SMALL) == 0
    printed = capsys.readouterr().out.splitlines()
    assert format_result(result).splitlines()[1:] == printed[1:]  # all but the timing


def test_ctrl_c_keeps_what_ran_exits_130_and_the_same_command_resumes(
    capsys, tmp_path, monkeypatch, in_process
):
    from puckboard.transfer import run as transfer_run

    real = transfer_run.run_sweep

    def stopped_after_one_episode(plan, scene, options):
        stopping = CountingExecutor(interrupt_after=1)
        return real(plan, scene, dataclasses.replace(options, executor=stopping, batch_size=1))

    monkeypatch.setattr(transfer_run, "run_sweep", stopped_after_one_episode)
    out = tmp_path / "runs.csv"
    assert main([*SMALL, "--out", str(out), "--json"]) == 130
    captured = capsys.readouterr()
    assert json.loads(captured.out)["ran"] == 1
    assert captured.err.strip().splitlines() == [
        f"puckboard transfer: interrupted; 1 episodes of this run kept in {out}; run the "
        "same command again to resume"
    ]
    monkeypatch.setattr(transfer_run, "run_sweep", real)
    assert main([*SMALL, "--out", str(out), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert (data["skipped"], data["ran"]) == (1, EPISODES - 1)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (["--families", "nois"], "no family 'nois' (did you mean 'noise'?); families: noise, "),
        (["--families", ","], "--families: name at least one family"),
        (["--seeds", "5:1"], "--seeds '5:1' is empty"),
        (["--profile", "epuck-3"], "unknown robot profile 'epuck-3'"),
        (["--controller", "nosuch"], "nosuch"),
        (["--plot", "figure.txt"], "--plot 'figure.txt': use a .png, .svg or .pdf file name"),
        (["--out", "runs.txt"], "use a .csv or .parquet file name"),
        (["--workers", "0"], "--workers must be at least 1"),
        (["--set", "noise.proximity=0.1"], "--set noise.proximity: the family 'noise' decides it"),
        (["--set", "control.period=0.1,0.2"], "--set control.period: give one value"),
        (["--set", "variation=reality-gap"], "the robots are --profile's and each family's to say"),
        (["--set", "control.period"], "expected PARAM=V1,V2,..."),
    ],
)
def test_mistakes_are_one_line_before_anything_runs(capsys, tmp_path, monkeypatch, change, message):
    monkeypatch.chdir(tmp_path)
    args = list(SMALL)
    flag, value = change
    if flag in args:
        args[args.index(flag) + 1] = value
    else:
        args += [flag, value]
    assert main(args) == 2
    assert message in one_error_line(capsys)


def test_a_scene_named_twice_or_missing_is_one_line(capsys):
    assert main([*SMALL[:2], "line-follow", *SMALL[2:]]) == 2
    assert "scene listed twice" in one_error_line(capsys)
    assert main(["transfer", "no-such-scene", "--seeds", "0:1", "--workers", "1"]) == 2
    assert "no-such-scene" in one_error_line(capsys)


def test_the_command_is_listed(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    assert "transfer" in capsys.readouterr().out
