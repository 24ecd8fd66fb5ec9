"""Values that start with a minus ('--seeds -5:2', '--distance -5mm') reach the check
that says what is wrong with them, instead of argparse's "expected one argument"
(issue 30, round 4, item 13)."""

from __future__ import annotations

import pytest

from puckboard.cli import main


@pytest.mark.parametrize(
    ("argv", "says"),
    [
        (
            ["sweep", "--seeds", "-5:2", "--workers", "1"],
            "--seeds '-5:2': seeds cannot be negative",
        ),
        (
            ["calibrate", "ir", "--distance", "-5mm"],
            "--distance: distance must be more than 0 and at most 150 mm, got -5 mm",
        ),
    ],
)
def test_a_negative_value_is_checked_as_a_value(argv, says, capsys):
    assert main(argv) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line == f"puckboard {argv[0]}: error: {says}"
    assert "expected one argument" not in line


def test_an_option_is_still_an_option(capsys):
    """Only a minus followed by a digit is taken as a value: '-q' stays the option."""
    assert main(["sweep", "--seeds", "-q"]) == 2
    assert "expected one argument" in capsys.readouterr().err
