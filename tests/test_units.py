"""Quantities with their units are read one way, wherever a user gives one."""

from __future__ import annotations

import math

import pytest

from puckboard.units import read_quantity


@pytest.mark.parametrize(
    ("text", "unit", "si"),
    [
        ("20.3mm", "m", 0.0203),
        ("3.1 cm", "m", 0.031),
        ("0.031", "m", 0.031),
        ("100ms", "s", 0.1),
        ("0.05s", "s", 0.05),
        ("17deg", "rad", math.radians(17)),
        (2, "1", 2.0),
    ],
)
def test_a_number_with_its_unit_is_its_si_value(text, unit, si):
    assert read_quantity("x", text, unit) == si


@pytest.mark.parametrize(
    ("value", "unit", "said"),
    [
        ("5deg", "m", "x = '5deg': unit 'deg' does not fit; metres, or with a unit: 31mm"),
        ("50mm", "s", "x = '50mm': unit 'mm' does not fit; seconds, or with a unit: 100ms"),
        ("fast", "s", "x = 'fast': expected a number (seconds, or with a unit: 100ms)"),
        (True, "s", "x = True: expected a number (seconds"),
        ("2mm", "1", "x = '2mm': unit 'mm' does not fit; a plain factor, no unit"),
    ],
)
def test_anything_else_is_one_line_that_says_how_to_write_it(value, unit, said):
    with pytest.raises(ValueError, match="^" + said.replace("(", r"\(").replace(")", r"\)")):
        read_quantity("x", value, unit)


def test_calibrate_reads_distances_as_every_quantity_is_read():
    from puckboard.cli.calibrate import length

    assert length("60mm") == read_quantity("d", "60mm", "m") == 0.06
    assert length("6cm") == 0.06
