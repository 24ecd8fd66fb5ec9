"""A profile file's ``[link]`` (what ``calibrate link`` writes) is one behaviour everywhere.

``run --profile FILE`` runs the simulator at the link's timing; so do ``sweep``,
``transfer`` and ``sensitivity``, whose episodes carry the link as ``profile.link.*``
parameters (each worker rebuilds the profile without the file); ``profiles show FILE``
and the transfer report show it. A simulated backend that cannot delay a command refuses
it, as it refuses any latency, naming where the latency came from.
"""

from __future__ import annotations

import csv
import json

import pytest

from puckboard.cli import main
from puckboard.control.episode import run_episode
from puckboard.errors import ProfileError
from puckboard.profile import load_profile_file
from puckboard.scenario import load_scene
from puckboard.sweep.plan import profile_parameters
from puckboard.transfer import choose_families, transfer_plan
from puckboard.transfer.plan import Skipped

LINK = """base = "epuck"
name = "link"

[link]
period = 0.096
latency = 0.034
source = "measured over Bluetooth"
"""


@pytest.fixture
def link_file(tmp_path):
    path = tmp_path / "link.toml"
    path.write_text(LINK, encoding="utf-8")
    return path


def test_the_link_travels_as_parameters_and_runs_as_run_runs_it(link_file):
    params = profile_parameters(load_profile_file(link_file))
    assert params == {
        "robot.profile": "epuck",
        "profile.link.period": 0.096,
        "profile.link.latency": 0.034,
    }
    result = run_episode("line-follow", controller="stock", overrides=params, duration=0.5)
    assert (result.control_period_s, result.control_latency_s) == (pytest.approx(0.1), 0.05)


def test_half_a_link_is_refused_in_one_line():
    with pytest.raises(ProfileError, match=r"give profile\.link\.latency too"):
        run_episode("line-follow", overrides={"profile.link.period": 0.1}, duration=0.1)


def test_a_sweeps_rows_record_the_link_it_ran_at(link_file, tmp_path, capsys):
    out = tmp_path / "rows.csv"
    args = ["sweep", "line-follow", "--controller", "stock", "--seeds", "0:1", "--duration"]
    code = main([*args, "0.5", "--profile", str(link_file), "--workers", "1", "--out", str(out)])
    assert code == 0
    (row,) = csv.DictReader(out.open(encoding="utf-8"))
    params = json.loads(row["params"])
    assert params["profile.link.period"] == 0.096 and params["profile.link.latency"] == 0.034


def test_profiles_show_shows_the_link(link_file, capsys):
    assert main(["profiles", "show", str(link_file)]) == 0
    out = capsys.readouterr().out
    assert "  link.period             96 ms\n  link.latency            34 ms\n" in out
    assert "      source: measured over Bluetooth" in out
    assert main(["profiles", "show", str(link_file), "--json"]) == 0
    shown = json.loads(capsys.readouterr().out)["link"]
    assert shown == {"period": 0.096, "latency": 0.034, "source": "measured over Bluetooth"}


def test_a_transfer_design_model_runs_at_the_link_and_says_so(link_file):
    from puckboard.sweep.run import SweepResult
    from puckboard.transfer import format_result
    from puckboard.transfer.result import TransferResult

    scene = load_scene("two-robot-pass")
    families = choose_families(["noise", "link epuck2-wifi", "period", "latency"])
    plan = transfer_plan(
        [scene], controllers=["stock"], profiles={scene.name: [load_profile_file(link_file)]},
        seeds=range(2), families=families,
    )  # fmt: skip
    design = next(p for p in plan.points if p.family == "design")
    assert design.params["profile.link.period"] == 0.096
    wifi = next(p for p in plan.points if p.family == "link epuck2-wifi")
    assert wifi.params["control.period"] == 0.1 and wifi.params["control.latency"] == 0.05
    why = "its grid starts at one step without delay, and this profile runs at the link it measured"
    assert Skipped(scene.name, "period", f"{why} ([link])", "link") in plan.skipped
    assert Skipped(scene.name, "latency", f"{why} ([link])", "link") in plan.skipped
    result = TransferResult.of(plan, [SweepResult(plan=s, outcomes=[]) for s in plan.sweeps])
    text = format_result(result)
    assert "two-robot-pass · link (its [link]: control every 100 ms, 50 ms latency)" in text


@pytest.mark.parametrize(
    ("args", "said"),
    [
        (
            ["--profile", "{link}"],
            "the profile's [link] (link) gives control.latency = 0.05 s, which the embedded "
            "backend alone simulates (this backend cannot delay a command); run it with "
            "--backend embedded",
        ),
        (
            ["--variation", "reality-gap"],
            "--variation reality-gap drew a real link's timing: control.latency drawn per "
            "cycle (median",
        ),
        (
            ["--set", "control.latency=0.05"],
            "control.latency = 0.05 s is simulated by the embedded backend only",
        ),
        (
            ["--set", "control.repeated=0.2"],
            "control.repeated = 0.2 is simulated by the embedded backend only",
        ),
    ],
)
def test_one_rule_on_a_backend_that_cannot_delay_a_command(link_file, capsys, args, said):
    given = [a.format(link=link_file) for a in args]
    assert main(["run", "line-follow", "--backend", "fake", "--duration", "0.5", *given]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.startswith(f"puckboard run: error: {said}")
