"""The tuning study the sweeps page shows agrees with itself.

The study takes minutes (the page gives its command and what it cost), so it is not run
here; what can be checked without it is: each cell's interval is the Wilson interval of
its counts, the rates are the counts', the worst and mean are the cells', the episode
counts are what 12 trials of 16 seeds on 2 cells make, and the line to use it holds the
best parameters.
"""

from __future__ import annotations

import re
from pathlib import Path

from puckboard.sweep.stats import wilson_interval

PAGE = Path(__file__).resolve().parents[2] / "docs" / "sweeps.md"


def shown() -> str:
    text = PAGE.read_text(encoding="utf-8")
    start = text.index("## Tuning: numbers for the worst robot")
    block = re.search(r"```text\n(.*?)```", text[start:], re.DOTALL)
    assert block is not None
    return block.group(1)


CELL = re.compile(
    r"^two-robot-pass, (\S+)\s+"
    r"([\d.]+) % \((\d+)–(\d+) %, (\d+)/(\d+)\)\s+([\d.]+) % \((\d+)–(\d+) %, (\d+)/(\d+)\)$",
    re.MULTILINE,
)


def test_each_cell_s_rates_and_intervals_are_its_counts():
    cells = CELL.findall(shown())
    assert [c[0] for c in cells] == ["epuck", "epuck-vrep"]
    design_rates = []
    for cell in cells:
        for rate, low, high, wins, n in (cell[1:6], cell[6:11]):
            w, total = int(wins), int(n)
            assert float(rate) == round(100 * w / total, 1)
            lo, hi = wilson_interval(w, total)
            assert (int(low), int(high)) == (round(100 * lo), round(100 * hi))
        design_rates.append(int(cell[4]) / int(cell[5]))
    summary = re.search(r"worst cell ([\d.]+) %, mean ([\d.]+) %", shown())
    assert summary is not None
    assert float(summary.group(1)) == round(100 * min(design_rates), 1)
    assert float(summary.group(2)) == round(100 * sum(design_rates) / 2, 1)


def test_the_episode_counts_and_the_line_to_use_are_the_study_s():
    text = shown()
    counts = re.search(r"pruning spared (\d+) of (\d+) design episodes", text)
    assert counts is not None
    assert int(counts.group(2)) == 12 * 16 * 2  # trials × design seeds × cells
    assert int(counts.group(1)) % (4 * 2) == 0  # whole rounds of 4 seeds on 2 cells
    inner = re.search(r"inner_factor\s+= ([\d.]+)", text)
    turn = re.search(r"turn_speed = ([\d.]+)", text)
    assert inner is not None and turn is not None
    assert (
        f"--set layer.LineFollow.inner_factor={inner.group(1)} "
        f"--set layer.FrontObstacleLeftTurn.turn_speed={turn.group(1)}"
    ) in text
