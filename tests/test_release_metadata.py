"""One version everywhere a reader looks: ``puckboard --version``, the changelog's top
entry and CITATION.cff, so a course or a paper cites the version it used."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from puckboard import __version__
from puckboard.cli import main

ROOT = Path(__file__).resolve().parents[1]
#: A changelog entry's heading: ``## 1.2.0 (2025-03-01)`` or ``## 1.2.0 (unreleased)``.
ENTRY = re.compile(r"^## (\d+\.\d+\.\d+\S*) \((unreleased|\d{4}-\d{2}-\d{2})\)$")


def top_entry() -> tuple[str, str]:
    headings = [
        line
        for line in (ROOT / "CHANGELOG.md").read_text(encoding="utf-8").splitlines()
        if line.startswith("## ")
    ]
    assert headings, "CHANGELOG.md has no entry"
    match = ENTRY.match(headings[0])
    assert match, f"the top entry's heading {headings[0]!r} is not '## X.Y.Z (date|unreleased)'"
    return match.group(1), match.group(2)


def citation() -> dict:
    yaml = pytest.importorskip("yaml")
    data = yaml.safe_load((ROOT / "CITATION.cff").read_text(encoding="utf-8"))
    assert isinstance(data, dict)
    return data


def test_the_command_line_prints_the_version_of_the_changelogs_top_entry(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["--version"])
    assert exit_.value.code == 0
    assert capsys.readouterr().out.strip() == f"puckboard {__version__}"
    assert top_entry()[0] == __version__


def test_the_citation_names_the_same_version_and_its_release_date():
    data = citation()
    version, date = top_entry()
    assert str(data["version"]) == version == __version__
    if date == "unreleased":
        assert "date-released" not in data
    else:
        assert str(data["date-released"]) == date


def test_the_citation_has_what_cff_1_2_0_requires_and_the_packages_licence():
    data = citation()
    assert data["cff-version"] == "1.2.0"
    assert data["message"].strip() and data["title"] == "puckboard"
    assert data["authors"] == [{"name": "The puckboard developers"}]
    pyproject = (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    assert f'license = {{ text = "{data["license"]}" }}' in pyproject
    assert data["abstract"].strip() and data["keywords"]
