"""docs/challenges.md documents every key of the file, every ranking key and verdict, as
the code reads and gives them."""

from __future__ import annotations

import re
from pathlib import Path

from puckboard.challenge import spec
from puckboard.challenge.standings import VERDICTS

PAGE = Path(__file__).resolve().parents[2] / "docs" / "challenges.md"


def table_after(text: str, header: str) -> dict[str, str]:
    """The first column (its code spans) -> the second, of the table whose header row is
    ``header``."""
    lines = text[text.index(header) :].splitlines()
    rows = {}
    for line in lines[2:]:
        if not line.startswith("|"):
            break
        first, second = [c.strip() for c in line.strip("|").split("|")][:2]
        for key in re.findall(r"`([^`]+)`", first):
            rows[key] = second
    return rows


def test_every_key_of_the_file_is_documented_and_no_other():
    text = PAGE.read_text(encoding="utf-8")
    tables = text.split("| key | meaning |")[1:]
    documented = [set(table_after("| key | meaning |" + t, "| key | meaning |")) for t in tables]
    top, limits, ranking, cell = documented
    assert top == {
        k if k not in ("limits", "ranking", "practice", "graded") else f"[{k}]" for k in spec._TOP
    }
    assert limits == set(spec._LIMITS)
    assert ranking == set(spec._RANKING)
    assert cell == set(spec._CELL)
    for key in spec.RANKING_KEYS:
        assert f"`{key}`" in text


def test_the_verdicts_table_is_the_code_s():
    table = table_after(PAGE.read_text(encoding="utf-8"), "| verdict | meaning |")
    assert {k: v.replace("`", "") for k, v in table.items()} == VERDICTS
