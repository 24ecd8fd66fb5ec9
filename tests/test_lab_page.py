"""The lab page (docs/lab-fragile-to-robust.md) shows what its commands print and quotes
its bands from the tables that measured them.

Each command the page shows with its output is run here as a reader runs it, in a
folder holding the tutorial's ``my_controller.py`` with the page's layer added, and
compared exactly (doc_pages). The runs are single episodes; the sensitivity analysis
and the tuning study take minutes, so their outputs are checked for agreeing with
themselves, with the controllers page's tables of the same episodes, and with one
row's episodes re-run. Every 200-seed figure the page quotes is the controllers page's.
"""

from __future__ import annotations

import itertools
import json
import re
import shlex
from pathlib import Path

import doc_pages
import numpy as np
import pytest
from cli_runs import run_in
from episodes import episode, episodes
from shared_sweeps import sweeps_share_episodes
from test_doc_claims import (
    BANDS,
    REPLAYS,
    ROBUST_BANDS,
    SHORT,
    band_key,
    cell_key,
    count_rate_interval,
    plain,
    stated_failures,
)

from puckboard.sweep.stats import wilson_interval

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "lab-fragile-to-robust.md"
PLAUSIBLE = {"variation": "plausible"}


def page() -> str:
    return PAGE.read_text(encoding="utf-8")


def stated(pattern: str) -> re.Match[str]:
    """The one place on the page that states ``pattern`` (whitespace-tolerant)."""
    found = list(re.finditer(pattern.replace(" ", r"\s+"), page(), re.DOTALL))
    assert len(found) == 1, f"the lab page states /{pattern}/ {len(found)} times, not once"
    return found[0]


def shown_commands() -> list[tuple[str, str]]:
    """Each ``puckboard`` command of a bash block that a text block follows, with that
    text (what the page says it prints)."""
    blocks = doc_pages.fences(page())
    pairs = []
    for (language, body), (next_language, shown) in itertools.pairwise(blocks):
        if language == "bash" and next_language == "text":
            (command,) = body.strip().splitlines()
            pairs.append((command, shown))
    return pairs


def shown_after(command_start: str) -> tuple[list[str], str]:
    (found,) = [(c, s) for c, s in shown_commands() if c.startswith(command_start)]
    return shlex.split(found[0])[1:], found[1]


# -- the student's file -------------------------------------------------------------------
@pytest.fixture(scope="module")
def student_folder(tmp_path_factory) -> Path:
    """``my_controller.py`` as the tutorial saves it, with the lab's layer and factory
    added as the page asks."""
    tutorial = (ROOT / "docs" / "tutorial.md").read_text(encoding="utf-8")
    saved = [b for lang, b in doc_pages.fences(tutorial) if b.startswith("# my_controller.py\n")]
    added = [b for lang, b in doc_pages.fences(page()) if lang == "python"]
    assert len(saved) == 1 and len(added) == 1, "one saved file, one addition to it"
    folder = tmp_path_factory.mktemp("lab")
    (folder / "my_controller.py").write_text(saved[0] + "\n\n" + added[0], encoding="utf-8")
    return folder


def run_cli(argv: list[str], folder: Path) -> str:
    """What ``puckboard ARGV`` prints when run in ``folder`` (in this process: cli_runs)."""
    status, printed = run_in(folder, argv)
    assert status == 0, f"{argv}: exit {status}"
    return printed


@pytest.mark.slow
def test_the_runs_and_the_replay_print_what_the_page_shows(student_folder):
    """The failing robot, its replay file, the graze and the guard's answer to it."""
    runs = [
        (c, s) for c, s in shown_commands() if c.startswith(("puckboard run", "puckboard replay"))
    ]
    assert len(runs) == 4, [c for c, _ in runs]
    for command, shown in runs:  # in page order: a replay needs its recording
        printed = run_cli(shlex.split(command)[1:], student_folder)
        doc_pages.assert_shown(shown, printed, f"lab page: {command}")
    assert (student_folder / "fail.html").is_file()
    recording = student_folder / "fail.npz"
    cruise_from = float(stated(r"from (\S+) s to the end of the run the layer").group(1))
    assert layers_of(recording, "right")[-1] == (cruise_from, "Cruise")
    grazed = float(stated(r"first collision, at (\S+) s").group(1))
    at_touch = state_at(student_folder / "graze.npz", "right", grazed)
    assert at_touch["layer"] == "FindLineOnTheRight", at_touch
    assert at_touch["right"] < 0.01, at_touch  # "less than 1 cm away"


def load(recording: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict]:
    with np.load(recording, allow_pickle=False) as z:
        return z["time"], z["layer"], z["proximity"], json.loads(str(z["meta"]))


def layers_of(recording: Path, robot: str) -> list[tuple[float, str]]:
    """(time, layer) each time the robot's driving layer changed."""
    time, layer, _, meta = load(recording)
    column, names = meta["robots"].index(robot), meta["robot_layers"][robot]
    changes = [0] + [i for i in range(1, len(time)) if layer[i, column] != layer[i - 1, column]]
    return [(round(float(time[i]), 2), names[layer[i, column]]) for i in changes]


def state_at(recording: Path, robot: str, t: float) -> dict[str, object]:
    from puckboard.records import PROX_NAMES

    time, layer, proximity, meta = load(recording)
    column, names = meta["robots"].index(robot), meta["robot_layers"][robot]
    i = int(np.argmin(np.abs(time - t)))
    return {
        "layer": names[layer[i, column]],
        "right": float(proximity[i, column, PROX_NAMES.index("right")]),
    }


def test_the_graze_is_the_controllers_page_s_replayed_one():
    """The seed the page records a graze on is the one the controllers page replays."""
    (graze,) = [r for r in REPLAYS if plain(r["run"]) == "the graze"]
    assert plain(graze["controller"]).startswith("my_controller")
    assert plain(graze["outcome"]) == "collision: robot right"
    command, _ = shown_after("puckboard run two-robot-pass --controller my_controller.py:my_")
    assert command[command.index("--seed") + 1] == graze["seed"]


# -- the figures quoted from the bands ----------------------------------------------------
def band(controller: str, profile: str) -> dict[str, str]:
    return {band_key(r): r for r in BANDS}[(controller, profile)]


def test_the_bands_the_page_quotes_are_the_controllers_page_s():
    improved = band("improved", "epuck")
    m = stated(r"shipped it passes (\d+) of 200 seeds \((\S+) %\)")
    shipped = plain(improved["shipped, of 200"])
    assert shipped.startswith(f"{m.group(1)} ({m.group(2)} %"), shipped
    m = stated(r"it passes \*\*(\d+) of 200 \(([^)]*)\)\*\*;\s+the failures are ([^.]*)\. Those")
    assert f"{m.group(1)} ({m.group(2)})" == plain(improved["plausible robots, of 200"])
    assert m.group(3) == stated_failures(improved["failures of plausible robots"])
    assert improved["plausible, seeds 0–9"] == "0"  # "none of seeds 0–9 passes"
    stated(r"on plausible robots none of seeds 0–9 passes")

    mine = band("my_controller (the tutorial's)", "epuck")
    m = stated(r"it passes\s+\*\*(\d+) of 200 \(([^)]*)\)\*\*, and the failures are (`\w+` \d+),")
    assert f"{m.group(1)} ({m.group(2)})" == plain(mine["plausible robots, of 200"])
    assert m.group(3) == stated_failures(mine["failures of plausible robots"])
    m = stated(r"On (\d+) runs with plausible robots, the tutorial's controller\s+never loses")
    rows = [r for r in BANDS if plain(r["controller"]).startswith("my_controller")]
    assert int(m.group(1)) == 200 * len(rows)
    assert all("lost_line" not in r["failures of plausible robots"] for r in rows)


def moves_it_most(controller: str) -> str:
    """The bands table's "what moves it most" cell, for the physical e-puck."""
    row = band(controller, "epuck")
    (column,) = [k for k in row if k.startswith("what moves it most")]
    return row[column]


def test_the_numbers_the_failures_hang_on_are_the_band_s():
    edge = moves_it_most("improved")
    m = stated(r"across the (\d+)–(\d+)° the sources give, the front sensors' heading moves\s+"
               r"the improved controller from (\d+) to (\d+) of 40 seeds")  # fmt: skip
    assert f"heading**, {m.group(1)}–{m.group(2)}°: {m.group(3)} to {m.group(4)} of 40" in edge
    graze = moves_it_most("my_controller (the tutorial's)")
    m = stated(r"the side sensors' inset, (\S+) mm, moves the tutorial's controller\s+from "
               r"(\d+) to (\d+) of 40 seeds, and IR gain from (\d+) to (\d+) of 40")  # fmt: skip
    inset, low, high, gain_low, gain_high = m.groups()
    assert f"inset, {inset} mm: {low} to {high} of 40" in graze
    assert f"IR gain, 0.7–1.3: {gain_low} to {gain_high} of 40" in graze


def test_the_robust_band_the_page_quotes_is_the_controllers_page_s():
    """ "200 of 200 validation seeds (...) in each of the four cells": every row's."""
    m = stated(
        r"robots it passed (\d+) of (\d+) validation seeds \((\S+) %, (\S+) %\) in each of "
        r"the four\s+cells"
    )
    four = [r for r in ROBUST_BANDS if r["conditions"] == "plausible" and "pass" in r["scene"]
            and "generated" not in r["scene"]]  # fmt: skip
    assert len(four) == 4
    for row in four:
        (column,) = [k for k in row if k.startswith("validation,")]
        runs = int(re.findall(r"\d+", column)[-1])
        count, numbers = count_rate_interval(row[column], runs)
        low_high = f"{numbers[1]:g}–{numbers[2]:g}"
        assert m.groups() == (str(count), str(runs), f"{numbers[0]:g}", low_high), row
    improved = plain(band("improved", "epuck")["plausible robots, of 200"])
    m = stated(r"where `improved` passes (\S+) % on the straight\s+meeting with the physical")
    assert f"({m.group(1)} %," in improved, improved


def test_the_robust_numbers_the_page_names_are_the_preset_s():
    from puckboard.behaviours import ClearanceGuard, LineSearch, load_controller

    layers = {type(layer): layer for layer in load_controller("robust").layers}
    m = stated(r"at a clearance of (\S+) .*; its search, `LineSearch`, .* at `ratio` (\S+)\.")
    assert float(m.group(1)) == layers[ClearanceGuard].clearance
    assert float(m.group(2)) == layers[LineSearch].ratio


# -- the sensitivity analysis -------------------------------------------------------------
ROW = re.compile(r"^(\S+(?: \(shipped\))?)\s+(\d+)\s+(\d+)\s+(\d+) %\s+\[(\d+), (\d+)\] %\s+(.*)$",
                 re.MULTILINE)  # fmt: skip


def sensitivity_shown() -> tuple[list[str], str]:
    return shown_after("puckboard sensitivity")


def test_the_sensitivity_output_agrees_with_itself_and_the_tables():
    argv, shown = sensitivity_shown()
    seeds = argv[argv.index("--seeds") + 1]
    assert seeds == "0:10"
    rows = ROW.findall(shown)
    assert [r[0] for r in rows] == ["10", "14", "17 (shipped)", "18"]
    for value, n, ok, rate, low, high, _ in rows:
        lo, hi = wilson_interval(int(ok), int(n))
        assert (int(low), int(high)) == (round(100 * lo), round(100 * hi)), value
        assert int(rate) == round(100 * int(ok) / int(n)), value
    # the shipped profile's row is the controllers page's seeds 0-9 figure for the cell
    (short,) = [r for r in SHORT if cell_key(r) == ("improved", "two-robot-pass", "epuck")]
    m = re.search(r"^shipped profile\s+(\d+) of 10 .*%\s+(\S.*)$", shown, re.MULTILINE)
    assert m is not None
    assert m.group(1) == short["success of seeds 0–9"]
    assert f"`{m.group(2).replace(' ', '` ', 1)}" == short["reported failures"]
    m = re.search(r"^--variation plausible\s+(\d+) of 10", shown, re.MULTILINE)
    assert m is not None and m.group(1) == band("improved", "epuck")["plausible, seeds 0–9"]
    spread = re.search(r"(\d+) %\s+(\d+) % at (\d+)°\s+(\d+) % at (\d+)°", shown)
    assert spread is not None
    rates = {r[0].split()[0]: int(r[3]) for r in rows}
    assert int(spread.group(1)) == max(rates.values()) - min(rates.values())


@pytest.mark.slow
def test_the_sensitivity_s_best_value_is_what_the_episodes_give():
    """The 10° row re-run: the front sensors turned to the low end of their range, as the
    analysis turns them."""
    from puckboard.profile import get_profile, uncertainty

    _, shown = sensitivity_shown()
    (row,) = [r for r in ROW.findall(shown) if r[0] == "10"]
    low = uncertainty(get_profile("epuck"))["prox_heading.front"].low
    assert round(np.degrees(low)) == 10
    overrides = {"profile.prox_heading.front": low}
    runs = [episode("two-robot-pass", "improved", s, "epuck", overrides) for s in range(10)]
    assert sum(r.success for r in runs) == int(row[2])


# -- the tuning study ---------------------------------------------------------------------
TRIAL = re.compile(
    r"^\| (\d+) \| ([\d.]+) \| ([\d.]+) \| (\d+) of (\d+) \| (\d+) of (\d+) \| ([^|]*)\|$",
    re.MULTILINE,
)


def tune_in(folder: Path, *extra: str) -> str:
    """The page's tune command, resumed from the study the docs ship: nothing is run."""
    argv, _ = shown_after("puckboard tune")
    study = argv[argv.index("--study") + 1]
    (folder / study).write_bytes((PAGE.parent / study).read_bytes())
    return run_cli([*argv, *extra], folder)


@pytest.mark.slow
def test_the_tuning_output_and_trials_are_the_stored_study_s(student_folder, tmp_path):
    """The page's output is the study's report; its trials table is the study's trials."""
    folder = tmp_path / "resumed"
    folder.mkdir()
    (folder / "my_controller.py").write_bytes((student_folder / "my_controller.py").read_bytes())
    _, shown = shown_after("puckboard tune")
    printed = tune_in(folder)
    first_shown, rest_shown = shown.strip().split("\n", 1)
    first_printed, rest_printed = printed.strip().split("\n", 1)
    doc_pages.assert_shown(rest_shown, rest_printed, "lab page: the tuning study")
    # "6 trials (6 run now, 0 from lab.journal; 2 pruned)": all were run when measured
    counts = r"^(\d+) trials \((\d+) run now, (\d+) from \S+; (\d+) pruned\)"
    ran, resumed = re.match(counts, first_shown), re.match(counts, first_printed)
    assert ran and resumed
    assert ran.group(1) == ran.group(2) == resumed.group(1) == resumed.group(3), first_shown
    assert ran.group(4) == resumed.group(4)

    report = json.loads(tune_in(folder, "--json"))
    rows = TRIAL.findall(page())
    assert [int(r[0]) for r in rows] == [t["number"] for t in report["trials"]]
    for row, trial in zip(rows, report["trials"]):
        params = list(trial["params"].values())
        assert [float(row[1]), float(row[2])] == [float(f"{v:g}") for v in params], row
        cells = [f"{c['successes']} of {c['episodes']}" for c in trial["cells"]]
        assert [f"{row[3]} of {row[4]}", f"{row[5]} of {row[6]}"] == cells, row
        pruned = f"pruned after {trial['rounds']} of {report['rounds']} rounds"
        assert (trial["state"] == "pruned") == (row[7].strip() == pruned), row
    assert rows[report["best"]["trial"]][7].strip() == "best"
    # trial 0 is the controller as written: the layers' own values
    from puckboard.behaviours import load_controller

    shipped = load_controller(f"{folder / 'my_controller.py'}:guarded_controller")
    own = {
        f"layer.{layer.name}.{attr}": getattr(layer, attr)
        for layer in shipped.layers
        for attr in ("clearance", "ratio")
        if hasattr(layer, attr)
    }
    assert report["trials"][0]["params"] == own
    # "trial 1's robots got further (0.86 laps against 0.81)"
    m = stated(r"trials (\d+) and (\d+) passed every\s+design episode, and trial \d+'s robots "
               r"got further \((\S+) laps against (\S+)\)")  # fmt: skip
    progress = []
    for number in (int(m.group(1)), int(m.group(2))):
        cells = report["trials"][number]["cells"]
        assert all(c["successes"] == c["episodes"] for c in cells)
        progress.append(f"{sum(c['mean_progress_laps'] for c in cells) / len(cells):.2f}")
    assert progress == [m.group(3), m.group(4)]
    m = stated(r"(\d+) of the (\d+) design episodes were never run")
    spared = report["episodes_spared_by_pruning"]
    assert (int(m.group(1)), int(m.group(2))) == (spared, report["design_episodes"] + spared)


def test_the_validation_intervals_the_page_reads_are_wilson_s():
    m = stated(r"(\d+) of (\d+) is\s+(\d+)–(\d+) %\. It says")
    count, n, low, high = (int(x) for x in m.groups())
    lo, hi = wilson_interval(count, n)
    assert (low, high) == (round(100 * lo), round(100 * hi))
    # "12 of 12 on both cells": the tuning's validation column
    argv, shown = shown_after("puckboard tune")
    first, last = (int(x) for x in argv[argv.index("--validate") + 1].split(":"))
    validation = re.findall(
        r"^two-robot-pass\S*, epuck .*\((\d+)–(\d+) %, (\d+)/(\d+)\)$", shown, re.MULTILINE
    )
    assert validation == [(str(low), str(high), str(count), str(n))] * 2, validation
    stated(
        rf"seeds {first}–{last - 1}, which no trial saw:\s+{count} of {n} on both cells, "
        "and no warning"
    )
    assert "warning" not in shown
    m = stated(r"a controller must pass (\d+) seeds of (\d+), without one\s+failure")
    needed = int(m.group(1))
    assert m.group(1) == m.group(2)
    assert wilson_interval(needed, needed)[0] >= 0.95 > wilson_interval(needed - 1, needed - 1)[0]


@pytest.mark.slow
def test_the_trials_bends_end_as_the_page_says(student_folder):
    """Trial 0 (the numbers as written) loses the line in the bend on seed 0, robot
    ``right`` first; the best trial's numbers pass the same seed."""
    spec = f"{student_folder / 'my_controller.py'}:guarded_controller"
    seed = int(stated(r"on seed (\d+) robot `right` loses the line").group(1))
    circling = episode("two-robot-pass-bend", spec, seed, "epuck", PLAUSIBLE)
    assert circling.failure == "lost_line"
    assert next(e for e in circling.events if e.kind == "lost_line").robot == "right"
    (best,) = [r for r in TRIAL.findall(page()) if r[7].strip() == "best"]
    tuned = {
        "layer.KeepClear.clearance": float(best[1]),
        "layer.FindLineOnTheRight.ratio": float(best[2]),
    }
    assert episode("two-robot-pass-bend", spec, seed, "epuck", {**PLAUSIBLE, **tuned}).success


WORDS = {"four": 4, "six": 6, "eight": 8, "twelve": 12}


def span(seeds: str) -> int:
    first, last = (int(x) for x in seeds.split(":"))
    return last - first


def test_the_words_around_the_commands_are_their_arguments():
    """ "Eight design seeds, six trials, ... twelve validation seeds per cell", and the
    lecturer notes' "runs 50 episodes" and "a study of six trials"."""
    argv, _ = shown_after("puckboard tune")
    m = stated(r"(\w+) design seeds, (\w+) trials, the best then run on (\w+) validation seeds")
    design, trials, validation = (WORDS[w.lower()] for w in m.groups())
    assert design == span(argv[argv.index("--seeds") + 1])
    assert trials == int(argv[argv.index("--trials") + 1])
    assert validation == span(argv[argv.index("--validate") + 1])
    notes = (ROOT / "docs" / "lecturer-notes.md").read_text(encoding="utf-8")
    _, shown = sensitivity_shown()
    episodes = re.search(r"(\d+) of \d+ episodes", shown)
    assert episodes is not None
    assert f"The sensitivity step runs {episodes.group(1)} episodes" in notes
    # the wall clock the notes quote is what the page's outputs printed, in order
    seconds = [
        f"{float(re.search(r', ([0-9.]+) s', text).group(1)):.0f} s"  # type: ignore[union-attr]
        for text in (
            shown,
            shown_after("puckboard tune")[1],
            shown_after("puckboard sweep two-robot-pass ")[1],
            shown_after("puckboard sweep two-robot-pass-bend ")[1],
        )
    ]
    flat = " ".join(notes.split())
    assert "they took {}, {}, and {} and {} of wall clock".format(*seconds) in flat, seconds
    assert f"a study of {next(w for w, n in WORDS.items() if n == trials)} trials" in " ".join(
        notes.split()
    )


SWEPT = re.compile(r"^\S+\s+-\s+(\d+)\s+(\d+)\s+(\d+) %\s+\[(\d+), (\d+)\] %\s+\S+\s+\S+\s+(.*)$",
                   re.MULTILINE)  # fmt: skip


def test_the_validation_sweeps_run_the_tuned_numbers_on_fresh_seeds():
    """The sweeps run the study's "use it" line on seeds no trial saw; each row's rate
    and interval are its counts'."""
    tune_argv, tune_shown = shown_after("puckboard tune")
    use = re.search(r"^use it:\n\s+(.*)$", tune_shown, re.MULTILINE)
    assert use is not None
    design = range(*(int(x) for x in tune_argv[tune_argv.index("--seeds") + 1].split(":")))
    read = {}
    for scene in ("two-robot-pass", "two-robot-pass-bend"):
        argv, shown = shown_after(f"puckboard sweep {scene} ")
        assert use.group(1) in " ".join(argv), argv
        seeds = range(*(int(x) for x in argv[argv.index("--seeds") + 1].split(":")))
        assert not set(seeds) & set(design)
        ((n, ok, rate, low, high, failures),) = SWEPT.findall(shown)
        assert int(n) == len(seeds)
        lo, hi = wilson_interval(int(ok), int(n))
        assert (int(low), int(high)) == (round(100 * lo), round(100 * hi))
        assert int(rate) == round(100 * int(ok) / int(n))
        failed = sum(int(x) for x in re.findall(r"\d+", failures))
        assert failed == int(n) - int(ok), failures
        read[scene] = (int(ok), int(n), int(low), int(high), failures.strip())
    m = stated(r"On the straight meeting, (\d+) of (\d+): the interval's lower end just reaches "
               r"(\d+) %\. In the\s+bend, (\d+) of (\d+) \((\d+)–(\d+) %\), and (\d+) runs "
               r"ended in `(\w+)`")  # fmt: skip
    ok, n, low, *_ = read["two-robot-pass"]
    assert m.groups()[:3] == (str(ok), str(n), str(low))
    ok, n, low, high, failures = read["two-robot-pass-bend"]
    kind, count = failures.split()
    assert m.groups()[3:] == (str(ok), str(n), str(low), str(high), count, kind)


# -- from robust to real: the transfer ----------------------------------------------------
def transfer_shown() -> tuple[list[str], str]:
    return shown_after("puckboard transfer")


BAND = r"(\d+)/(\d+) \[(\d+), (\d+)\] %"


def shown_row(label: str) -> str:
    """What the page's transfer output shows for one model (its row's cell)."""
    row = re.search(rf"^{re.escape(label)}\s+(\S.*)$", transfer_shown()[1], re.MULTILINE)
    assert row is not None, label
    return row.group(1)


def absolute(spec: str, folder: Path) -> str:
    """A command's ``my_controller.py:FACTORY`` with the file's absolute path."""
    file, _, factory = spec.partition(":")
    assert (folder / file).is_file(), spec
    return f"{folder / file}:{factory}"


@pytest.mark.slow
def test_the_transfer_prints_what_the_page_shows_and_its_run_that_breaks_fails(student_folder):
    """The page's transfer as the reader runs it, then the ``puckboard run`` the page
    says is the first seed that failed at 100 ms: the seeds before it passed, it fails.
    The controller file is named by its absolute path (its label does not show it), so
    that the run's episodes are the transfer's (tests/support/shared_sweeps.py). One
    test, so that the transfer runs in one worker process only."""
    from puckboard.cli import build_parser
    from puckboard.sweep.plan import parse_set

    argv, shown = transfer_shown()
    at = argv.index("--controller") + 1
    argv[at] = absolute(argv[at], student_folder)
    with sweeps_share_episodes():
        printed = run_cli([*argv, "--quiet"], student_folder)
    doc_pages.assert_shown(shown, printed, "lab page: the transfer")

    m = stated(r"`(puckboard run two-robot-pass --controller my_controller\S* [^`]*)` is the "
               r"first seed that failed at\s+(\d+) ms")  # fmt: skip
    run = shlex.split(m.group(1))
    assert build_parser().parse_args(run[1:]).command == "run"
    overrides = dict(PLAUSIBLE)
    for i, word in enumerate(run):
        if word == "--set":
            name, (value,) = parse_set(run[i + 1])
            overrides[name] = value
    assert overrides["control.latency"] * 1000 == pytest.approx(float(m.group(2)))
    assert run[run.index("--profile") + 1] == argv[argv.index("--profile") + 1]
    spec = absolute(run[run.index("--controller") + 1], student_folder)
    seed = int(run[run.index("--seed") + 1])
    first = int(re.search(r"; seeds (\d+):", shown).group(1))  # type: ignore[union-attr]
    runs = episodes("two-robot-pass", spec, range(first, seed + 1), "epuck", overrides)
    assert [r.success for r in runs] == [True] * (seed - first) + [False]


def test_the_transfer_judges_the_tuned_numbers_on_seeds_no_step_used():
    """The tuning's "use it" line, on the transfer's default seeds (none of the lab's),
    with every link the page's table names and the family of its radius."""
    from puckboard.sweep.defaults import TRANSFER_SEEDS as DEFAULT_SEEDS
    from puckboard.sweep.plan import parse_seeds

    argv, shown = transfer_shown()
    _, tune_shown = shown_after("puckboard tune")
    use = re.search(r"^use it:\n\s+(.*)$", tune_shown, re.MULTILINE)
    assert use is not None and use.group(1) in shlex.join(argv)
    assert "--seeds" not in argv
    seeds = parse_seeds(DEFAULT_SEEDS)
    assert f"; seeds {DEFAULT_SEEDS} at every model" in shown
    used = []  # every seed range the lab's other commands run
    for command, _ in shown_commands():
        words = shlex.split(command)
        used += [words[i + 1] for i, w in enumerate(words) if w in ("--seeds", "--validate")]
    assert len(used) == 5 and all(parse_seeds(u).stop <= seeds.start for u in used), used
    stated(rf"every model on the same seeds, from {seeds.start} on: seeds none of the steps")
    families = argv[argv.index("--families") + 1].split(",")
    table = re.findall(r"^\| [^|]+ \| `(link [\w-]+)` \|$", page(), re.MULTILINE)
    assert families == [*table, "latency"], (families, table)


def test_the_words_around_the_transfer_are_its_output():
    """What the page says of the output is the output's (which the test above compares
    with a run), the links' sources' and the plan's."""
    from puckboard.profile.links import get_link
    from puckboard.scenario.scenefile import load_scene
    from puckboard.sweep.plan import parse_set
    from puckboard.transfer import FAMILIES, seeds_for_lower_bound, transfer_plan
    from puckboard.transfer.families import link_timing

    argv, shown = transfer_shown()
    n = span(re.search(r"; seeds (\S+) at every model", shown).group(1))  # type: ignore[union-attr]
    design = re.fullmatch(BAND, shown_row("design"))
    assert design is not None
    four = stated(r"on (\w+) fresh seeds: (\d+) of (\d+)\.\s+(\w+) seeds are a screen, not a "
                  r"verdict: (\d+) of (\d+) is (\d+)–(\d+) %\.").groups()  # fmt: skip
    assert WORDS[four[0]] == WORDS[four[3].lower()] == n
    assert four[1:3] == design.groups()[:2]
    assert four[4:] == (str(n), str(n), *(str(round(100 * x)) for x in wilson_interval(n, n)))
    # the two slow links share one loop; USB's slow end is the design loop
    dt = load_scene("two-robot-pass").dt
    m = stated(
        r"a period of (\d+) ms and a latency of (\d+) ms, so the two rows are one\s+set "
        r"of episodes: (\d+) of (\d+)\. Over USB the slow end \((\d+) ms, (\d+) ms\)"
    )
    for link in ("epuck2-wifi", "bluetooth-sercom"):
        timing = link_timing(link, dt)
        ms = (round(1000 * timing["control.period"]), round(1000 * timing["control.latency"]))
        assert (m.group(1), m.group(2)) == tuple(str(x) for x in ms), link
        assert f"link {link}: period {ms[0]} ms, latency {ms[1]} ms: " in shown
        band = re.fullmatch(BAND, shown_row(f"link {link}"))
        assert band is not None and band.groups()[:2] == (m.group(3), m.group(4))
    usb = get_link("usb-sercom")
    assert (m.group(5), m.group(6)) == (f"{1000 * usb.period[1]:g}", f"{1000 * usb.latency[1]:g}")
    assert (
        "link usb-sercom: not run, at two-robot-pass's 50 ms step its slow end is the design"
        in shown
    )
    # the radius as shown, and read in words
    radius = shown_row("radius: latency")
    quoted = re.escape(radius).replace("\\ ", " ")  # stated() takes a space for any
    stated(rf"\*\*The radius\*\*, `{quoted}`, reads")
    read = re.fullmatch(rf"(\d+) ms: {BAND}; (\d+) ms (\d+)/(\d+)", radius)
    assert read is not None
    words = stated(r"up to a latency of (\d+) ms\s+\((\d+) of (\d+) there, its interval "
                   r"(\d+)–(\d+) %\), and (\d+) ms is the first step where it did not\s+"
                   r"\((\d+) of (\d+)\)").groups()  # fmt: skip
    assert words == read.groups()
    (latency,) = [f for f in FAMILIES if f.name == "latency"]
    m = stated(
        r"delays\s+every command by (\d+), (\d+) and (\d+) steps \((\d+), (\d+) and (\d+) ms\)"
    )
    assert [float(x) for x in m.groups()[:3]] == list(latency.grid)
    assert [int(x) for x in m.groups()[3:]] == [round(1000 * s * dt) for s in latency.grid]
    assert f"grid {', '.join(f'{x} ms' for x in m.groups()[3:])}; " in shown
    # the links' sources against the radius
    m = stated(r"The Wi-Fi link's sources put its latency at (\d+) ms at most, inside\s+the "
               r"radius; Bluetooth's slow end, (\d+) ms, is assumed")  # fmt: skip
    wifi, bluetooth = get_link("epuck2-wifi").latency[1], get_link("bluetooth-sercom").latency[1]
    assert (m.group(1), m.group(2)) == (f"{1000 * wifi:g}", f"{1000 * bluetooth:g}")
    assert 1000 * wifi <= int(read.group(1)) < 1000 * bluetooth < int(read.group(6))
    stated(r"falls in that gap, and its row ran it rounded to one step\.")
    assert link_timing("bluetooth-sercom", dt)["control.latency"] == pytest.approx(dt)
    profiles = (ROOT / "docs" / "profiles.md").read_text(encoding="utf-8")
    # the links' ranges table comes first; the per-cycle table below it has a row too
    row_text = next(r for r in profiles.splitlines() if r.startswith("| `bluetooth-sercom`"))
    assert "latency high: assumed" in row_text
    m = stated(r"the lower end of an interval reaches 95 % only from (\d+) of (\d+)")
    assert int(m.group(1)) == int(m.group(2)) == seeds_for_lower_bound()
    # "every family on this cell, 60 episodes"
    fixed = dict(parse_set(argv[i + 1]) for i, w in enumerate(argv) if w == "--set")
    scene = load_scene("two-robot-pass")
    every = transfer_plan(
        [scene], controllers=[argv[argv.index("--controller") + 1]],
        profiles={scene.name: [argv[argv.index("--profile") + 1]]}, seeds=range(n),
        families=FAMILIES, fixed={k: v[0] for k, v in fixed.items()},
        replacements={"generated-pass": load_scene("generated-pass")},
    )  # fmt: skip
    stated(rf"every family on this cell, {len(every)} episodes")


def test_the_lecturer_notes_count_the_transfer_s_episodes():
    """ "The last step's transfer runs 16 episodes": what the page's output counts."""
    _, shown = transfer_shown()
    counted = re.match(r"transfer: (\d+) of \1 episodes", shown)
    assert counted is not None
    notes = " ".join((ROOT / "docs" / "lecturer-notes.md").read_text(encoding="utf-8").split())
    assert f"The last step's transfer runs {counted.group(1)} episodes" in notes
