"""What the command line did silently now says so, or does what was asked
(issue 30, round 4, item 16)."""

from __future__ import annotations

import io
import os
import re
from pathlib import Path

import pytest

from puckboard.cli import build_parser, main

SMALL = ["sweep", "--seeds", "0:1", "--duration", "0.2", "--workers", "1", "-q"]


def test_plot_param_without_plot_is_refused(capsys):
    assert main([*SMALL, "--set", "noise.proximity=0,0.1", "--plot-param", "noise.proximity"]) == 2
    line = capsys.readouterr().err.strip().splitlines()[-1]
    assert line.startswith("puckboard sweep: error: --plot-param chooses the x axis of --plot")


def test_sweep_help_names_the_option_that_seeds_the_variation():
    sub = build_parser()._subparsers._group_actions[0].choices  # type: ignore[union-attr]
    text = " ".join(sub["sweep"].format_help().split())
    assert "--seed " not in text and "--seed," not in text and "--seed)" not in text
    assert "seeded by each episode's seed from --seeds:" in text
    assert "seeded by --seed:" in " ".join(sub["run"].format_help().split())


def test_the_sweep_table_shows_values_as_written(capsys):
    argv = [*SMALL, "--set", "profile.prox_heading.front=12.7deg,0.3"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "profile.prox_heading.front=12.7deg " in out
    assert "profile.prox_heading.front=0.3 " in out
    assert "0.2216" not in out


def test_an_animation_alone_writes_no_plots_into_the_current_folder(tmp_path, monkeypatch, capsys):
    pytest.importorskip("PIL")
    run = tmp_path / "r.npz"
    assert main(["run", "line-follow", "--duration", "0.3", "--record", str(run), "--json"]) == 0
    here = tmp_path / "here"
    here.mkdir()
    monkeypatch.chdir(here)
    capsys.readouterr()
    assert main(["plot", str(run), "--animate", "a.gif"]) == 0
    assert sorted(os.listdir(here)) == ["a.gif"]
    # the frames are counted on stderr as they are drawn, the last line when all are
    said = capsys.readouterr()
    frames = re.search(r"\((\d+) frames, ", said.out)
    assert frames is not None
    n = frames.group(1)
    assert said.err.splitlines()[-1].startswith(f"plot --animate: {n}/{n} frames (100 %)")
    assert main(["plot", str(run), "--animate", "b.gif", "--out", "figs"]) == 0
    assert len(list(Path("figs").iterdir())) == 4  # asked for: still written


class _Pipe(io.StringIO):
    """stdout into a pipe: not a terminal; counts what was flushed."""

    def __init__(self) -> None:
        super().__init__()
        self.flushed: list[str] = []

    def isatty(self) -> bool:
        return False

    def flush(self) -> None:
        self.flushed.append(self.getvalue())


def test_monitor_into_a_pipe_shows_the_first_table_at_once_flushed():
    pytest.importorskip("rich")
    from rich.console import Console

    from puckboard.blackboard import Blackboard
    from puckboard.viz.monitor import SensorMonitor

    pipe = _Pipe()
    monitor = SensorMonitor(Blackboard(), ["a"], console=Console(file=pipe), plain_every=60.0)
    monitor()  # the first cycle: a table now, not after a minute
    assert pipe.flushed and pipe.flushed[-1] == pipe.getvalue() != ""
    monitor()  # the next within the minute: none
    assert pipe.getvalue() == pipe.flushed[-1]


@pytest.mark.parametrize("command", [["run"], SMALL])
def test_a_step_longer_than_the_control_can_act_on_is_refused_with_the_reason(command, capsys):
    assert main([*command, "--set", "dt=0.5"]) == 2
    line = capsys.readouterr().err.strip().splitlines()[-1]
    assert "dt 0.5 s is longer than the robots' control can act on" in line
    assert "crosses its IR range in 0.38 s" in line and "use dt ≤ 0.37 s" in line


@pytest.mark.parametrize(
    ("args", "said"),
    [
        (
            ["run", "--set", "control.period=0.1", "--set", "control.period=0.2"],
            "puckboard run: error: --set control.period given twice (control.period=0.1, "
            "then control.period=0.2); give it once",
        ),
        (
            ["scenes", "show", "generated-pass", "--seed", "7", "--seed", "8"],
            "puckboard scenes: error: --seed given twice (7, then 8); give it once",
        ),
        (
            ["run", "--duration", "1", "--duration=2"],
            "puckboard run: error: --duration given twice (1.0, then 2.0); give it once",
        ),
        (
            ["run", "--variation", "reality-gap", "--set", "variation=plausible"],
            "puckboard run: error: --variation reality-gap and --set variation=plausible: the "
            "variation is given twice; give it once",
        ),
        (
            ["scenes", "show", "generated-pass", "--seed", "-1"],
            "puckboard scenes: error: --seed must be a whole number ≥ 0, got -1",
        ),
    ],
)
def test_a_value_given_twice_or_a_bad_seed_is_one_line(capsys, args, said):
    """Which of two values was meant only the user knows (the last one once won without a
    word); a negative seed once ended in numpy's traceback."""
    assert main(args) == 2
    assert capsys.readouterr().err.strip().splitlines() == [said]


def test_the_python_api_refuses_two_variations_too():
    from puckboard.control.episode import run_episode

    with pytest.raises(ValueError, match="variation given twice: 'reality-gap' and, in the"):
        run_episode("line-follow", variation="reality-gap", overrides={"variation": "plausible"})


@pytest.mark.parametrize(
    ("latency", "said"),
    [
        ((0.0, 0.0), "no reply is held back: sync has no latency"),
        ((0.005, 0.005), "every reply is held back 5 ms, as on sync"),
        ((0.005, 0.04), "every reply is held back 5-40 ms, as on sync"),
    ],
)
def test_emulate_says_how_long_a_reply_is_held_back_without_a_range_of_nothing(latency, said):
    from puckboard.cli.emulate import held_back_text

    assert held_back_text("sync", latency) == said
