"""``run --help`` and ``sweep --help`` list the settings ``--set`` takes from the one
settings table, so a setting added there is in the help without editing it."""

from __future__ import annotations

import re

import pytest

from puckboard.cli import build_parser
from puckboard.scenario.settings import SETTINGS


@pytest.mark.parametrize("command", ["run", "sweep"])
def test_the_help_names_every_setting_of_the_table(command):
    subparsers = next(
        a for a in build_parser()._actions if a.__class__.__name__ == "_SubParsersAction"
    )
    text = " ".join(subparsers.choices[command].format_help().split())
    assert SETTINGS, "the table is not empty"
    for name in SETTINGS:
        assert re.search(rf"(?<![\w.]){re.escape(name)}\b", text), (command, name)
