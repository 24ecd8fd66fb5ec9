"""docs/transfer.md says what the code does: its families and grids, its counts, its
default seeds, the seeds the lower bound needs, and commands the CLI takes."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest

from puckboard.bench import transfer as bench
from puckboard.cli import build_parser
from puckboard.scenario.scenefile import load_scene
from puckboard.sweep.defaults import TRANSFER_SEEDS as DEFAULT_SEEDS
from puckboard.sweep.plan import parse_seeds
from puckboard.transfer import FAMILIES, seeds_for_lower_bound, transfer_plan

PAGE = (Path(__file__).resolve().parents[2] / "docs" / "transfer.md").read_text(encoding="utf-8")


def commands() -> list[str]:
    """The page's commands (its synopsis, with SCENE..., aside)."""
    return [
        line
        for line in PAGE.splitlines()
        if line.startswith("puckboard transfer ") and "SCENE..." not in line
    ]


def table_rows() -> dict[str, list[str]]:
    rows = {}
    for line in PAGE.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("| `") and len(cells) == 4:
            rows[cells[0]] = cells
    return rows


def test_every_command_on_the_page_parses():
    parser = build_parser()
    assert len(commands()) == 2
    for command in commands():
        args = parser.parse_args(shlex.split(command)[1:])
        assert args.command == "transfer"


def test_the_families_table_lists_every_family_with_its_grid():
    rows = table_rows()
    named = [n for row in rows for n in re.findall(r"`([^`]+)`", row)]
    assert sorted(named) == sorted(f.name for f in FAMILIES)
    for family in FAMILIES:
        (row,) = [r for key, r in rows.items() if f"`{family.name}`" in key]
        grid = row[3]
        if not family.grid:
            assert grid == "–"
            continue
        shown = [family.scale_text(s, 0.05).removesuffix(" ms") for s in family.grid]
        assert re.findall(r"[\d.]+", grid) == [s.removeprefix("×") for s in shown], family.name


def test_the_default_seeds_are_the_page_s_and_the_bench_s():
    seeds = parse_seeds(DEFAULT_SEEDS)
    assert f"`--seeds A:B` | seeds run on every model (default `{DEFAULT_SEEDS}`)" in PAGE
    assert (seeds.start, seeds.stop) == bench.FLAGSHIP_SEEDS
    assert f"seeds {seeds.start}–{seeds.stop - 1}" in PAGE
    assert (
        f"default of {['', 'one', 'two', 'three', 'four', 'five', 'six'][len(seeds)]} seeds" in PAGE
    )


def test_the_page_s_episode_counts_are_the_plans(tmp_path):
    plan, _ = bench.flagship_plan(len(parse_seeds(DEFAULT_SEEDS)), tmp_path)
    assert f"{len(plan):,} episodes" in PAGE
    scene = load_scene("two-robot-pass")
    one = transfer_plan(
        [scene], controllers=["robust"], profiles={scene.name: [scene.robots[0].profile]},
        seeds=parse_seeds("400:420"), families=FAMILIES,
        replacements={"generated-pass": load_scene("generated-pass")},
    )  # fmt: skip
    assert "(20 seeds, one\ncontroller, one profile, one scene: " in PAGE
    assert f"one scene: {len(one)} episodes)" in PAGE


def test_the_lower_bound_needs_the_seeds_the_page_names():
    n = seeds_for_lower_bound()
    assert f"only from **{n} seeds**" in PAGE
    assert f"--seeds 400:{400 + n}" in PAGE


@pytest.mark.parametrize("name", ["transfer.md"])
def test_the_page_is_in_the_navigation(name):
    nav = (Path(__file__).resolve().parents[2] / "mkdocs.yml").read_text(encoding="utf-8")
    assert f": {name}" in nav


def test_the_intervals_the_page_quotes_are_wilson_s():
    from puckboard.sweep.stats import wilson_interval

    for n in (20, len(parse_seeds(DEFAULT_SEEDS))):
        low = wilson_interval(n, n)[0]
        assert f"{n} of {n} is {100 * low:.0f}–100 %" in PAGE.replace("\n", " ")


def test_the_measured_time_s_arithmetic_holds():
    """The CPU seconds are user + sys as /usr/bin/time printed them, and the two-core
    figure is half of them, in minutes and seconds."""
    text = PAGE.replace("\n", " ")
    cpu, user, system = (
        float(x)
        for x in re.search(
            r"used (\d+) s of CPU \(`/usr/bin/time`: ([\d.]+) s user, ([\d.]+) s sys\)", text
        ).groups()
    )
    assert cpu == round(user + system)
    minutes, seconds = divmod(round((user + system) / 2), 60)
    assert f"**{minutes} min {seconds} s, is what two idle cores take**" in text
    assert minutes * 60 + seconds <= bench.TARGET_S


def test_the_bench_s_measurement_is_half_its_cpu_seconds_and_within_target():
    text = PAGE.replace("\n", " ")
    cpu = float(re.search(r"the workers ([\d.]+) CPU seconds: ", text).group(1))
    minutes, seconds = divmod(round(cpu / 2), 60)
    assert f"CPU seconds: {minutes} min {seconds} s on two idle cores" in text
    assert cpu / 2 <= bench.TARGET_S


# -- robust's radii, as docs/controllers.md shows them (measured, not re-run here) -------
CONTROLLERS = (Path(__file__).resolve().parents[2] / "docs" / "controllers.md").read_text(
    encoding="utf-8"
)
BAND = re.compile(r"(\d+)/(\d+) \[(\d+), (\d+)\] %")


def robust_transfer() -> tuple[list[str], list[list[str]]]:
    """The command and the table of `puckboard transfer` on `robust`."""
    lines = CONTROLLERS.splitlines()
    (command,) = [
        line.removeprefix("$ ")
        for line in lines
        if line.startswith("$ puckboard transfer ") and "--controller robust" in line
    ]
    start = lines.index(
        "| model | straight, `epuck` | straight, `epuck-vrep` | bend, `epuck` | "
        "bend, `epuck-vrep` |"
    )
    rows = []
    for line in lines[start + 2 :]:
        if not line.startswith("|"):
            break
        rows.append([c.strip() for c in line.strip().strip("|").split("|")])
    return shlex.split(command), rows


def test_robust_s_transfer_command_parses_and_its_episode_count_is_the_plan_s():
    argv, _ = robust_transfer()
    args = build_parser().parse_args(argv[1:])
    scenes = [load_scene(name) for name in args.scenario]
    plan = transfer_plan(
        scenes, controllers=args.controller,
        profiles={s.name: list(args.profile) for s in scenes},
        seeds=parse_seeds(args.seeds), families=FAMILIES,
        replacements={"generated-pass": load_scene("generated-pass")},
    )  # fmt: skip
    assert f"({len(plan):,} episodes;" in CONTROLLERS


def test_robust_s_transfer_bands_and_radii_agree_with_themselves():
    """Every figure is of the command's seeds, with its Wilson interval; a radius's point
    keeps 95 % and the first point beyond it does not."""
    from puckboard.sweep.stats import wilson_interval

    argv, rows = robust_transfer()
    n = len(parse_seeds(argv[argv.index("--seeds") + 1]))
    assert {r[0] for r in rows} >= {"design band", "reality-gap", "radius: noise"}
    for model, *cells in rows:
        assert len(cells) == 4, model
        for cell in cells:
            k, runs, low, high = (int(x) for x in BAND.search(cell).groups())
            assert runs == n, (model, cell)
            assert [round(100 * x) for x in wilson_interval(k, runs)] == [low, high], cell
            if not model.startswith("radius: "):
                continue
            assert k / runs >= 0.95, (model, cell)
            beyond = re.search(r"; .+ (\d+)/(\d+)$", cell)
            assert (beyond is None) == cell.startswith("≥ "), cell
            if beyond:
                assert int(beyond.group(1)) / int(beyond.group(2)) < 0.95, (model, cell)
